#include "rpAxisGuidance.h"

#include <cmath>

namespace rp {

void AxisGuidance::Evaluate(const FixtureTuning& t, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& m,
                            FixtureForce& out) const noexcept {
  (void)goal;
  out = FixtureForce{};
  const Vec3 offset = this->Axis.Offset(tool.Tip);
  const double radial = Norm(offset);
  const double depth = this->Axis.Depth(tool.Tip);
  const double reach = m.Engaged ? t.Release : t.Capture;
  m.Distance = radial;
  m.Engaged = radial <= reach && depth <= this->Axis.Length() + reach;
  m.Proxy = tool.Tip - offset;  // the foot on the axis
  const Vec3& u = this->Axis.Direction();
  Vec3 across{};  // the tool's velocity across the axis (free along it)
  if (m.HasLast && dt > 0) {
    const Vec3 v = (tool.Tip - m.LastTip) / dt;
    across = v - u * Dot(v, u);
  }
  m.LastTip = tool.Tip;
  m.LastProxy = m.Proxy;
  m.HasLast = true;
  out.Spring = offset * -t.Stiffness;
  out.Damper = across * -t.Damping;
  out.Stiffness = t.Stiffness;
  out.Direction = u;
  out.Across = true;
  out.Stored = 0.5 * t.Stiffness * radial * radial;
  out.Engaged = m.Engaged;
  // Orientation: turn the tool's direction towards the axis's (about their common normal).
  if (t.AngularStiffness > 0 && Norm2(tool.Direction) > 0) {
    const Vec3 turn = Cross(tool.Direction, u);
    const double s = Norm(turn);
    const double angle = std::atan2(s, Dot(tool.Direction, u));
    if (s > 1e-12) out.Torque = turn * (t.AngularStiffness * angle / s);
  }
}

}  // namespace rp
