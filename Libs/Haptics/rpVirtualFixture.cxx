#include "rpVirtualFixture.h"

#include <algorithm>

namespace rp {

const char* FixtureKindName(FixtureKind kind) {
  switch (kind) {
    case FixtureKind::SurfaceConstraint: return "surface";
    case FixtureKind::AxisGuidance: return "axis";
    case FixtureKind::DepthStop: return "depth";
    case FixtureKind::ForbiddenRegion: return "forbidden";
  }
  return "?";
}

void WallContactForce(const FixtureTuning& t, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& m,
                      FixtureForce& out) noexcept {
  out = FixtureForce{};
  const Vec3 tipVelocity = m.HasLast && dt > 0 ? (tool.Tip - m.LastTip) / dt : Vec3{};
  const Vec3 goalVelocity = m.HasLast && dt > 0 ? (goal - m.LastProxy) / dt : Vec3{};
  m.LastTip = tool.Tip;
  m.LastProxy = goal;
  m.HasLast = true;
  out.Engaged = m.Contact;
  if (!m.Contact) return;
  const Vec3& n = m.ContactNormal;
  const double press = Dot(goal - tool.Tip, n);  // > 0: the hand is past the wall's proxy
  if (press <= 0) return;
  // eq. 1–3 along the wall's normal; the damper may soften the push but a wall never pulls.
  const double spring = t.Stiffness * press;
  const double damper = std::max(-spring, t.Damping * Dot(goalVelocity - tipVelocity, n));
  out.Spring = n * spring;
  out.Damper = n * damper;
  out.Stiffness = t.Stiffness;
  out.Direction = n;
  out.Stored = 0.5 * t.Stiffness * press * press;
}

}  // namespace rp
