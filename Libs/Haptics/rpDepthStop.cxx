#include "rpDepthStop.h"

namespace rp {

bool DepthStop::Allowed(const FixtureTuning& t, const Vec3& p, double radius, FixtureMemory& m) const noexcept {
  (void)radius;
  m.Distance = this->Axis.Length() - this->Axis.Depth(p);
  return m.Distance >= 0 || this->Axis.Distance(p) > t.Capture;
}

Vec3 DepthStop::Constrain(const FixtureTuning& t, const Vec3& from, const Vec3& to, double radius,
                          FixtureMemory& m) const noexcept {
  (void)radius;
  const double stop = this->Axis.Length();
  const double capture = t.Capture;
  const double d1 = this->Axis.Depth(to);
  m.Distance = stop - d1;
  const Vec3 onWall = to - this->Axis.Direction() * (d1 - stop);  // `to` slid back onto the wall
  if (d1 <= stop) {
    m.Contact = false;
    return to;
  }
  if (m.Contact) {  // sliding on the wall since the last tick: it holds while within the capture radius
    m.Contact = this->Axis.Distance(onWall) <= capture;
    return m.Contact ? onWall : to;
  }
  const double d0 = this->Axis.Depth(from);
  if (d0 > stop) return to;  // one-sided: the move starts beyond the wall
  // Swept: where the segment crosses the wall's plane, and whether that is on the wall.
  const double share = d1 > d0 ? (stop - d0) / (d1 - d0) : 0.0;
  const Vec3 crossing = from + (to - from) * share;
  if (this->Axis.Distance(crossing) > capture) return to;  // passes beside the wall
  m.Contact = true;
  m.ContactNormal = -this->Axis.Direction();
  return onWall;
}

void DepthStop::Evaluate(const FixtureTuning& t, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& m,
                         FixtureForce& out) const noexcept {
  WallContactForce(t, tool, goal, dt, m, out);
}

}  // namespace rp
