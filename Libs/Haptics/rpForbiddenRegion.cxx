#include "rpForbiddenRegion.h"

#include <algorithm>
#include <cmath>

namespace rp {

namespace {
constexpr int AdvanceSteps = 12;    // conservative-advancement steps per move (each one BVH query)
constexpr int SlideSteps = 3;       // sliding: steps along the wall per tick ...
constexpr double SlideStep = 0.15;  // ... of at most this (mm): 0.45 mm a tick, 450 mm/s
constexpr double SlideGap = 0.03;   // mm above the offset surface once in contact: a step's chord
                                    // (0.15 mm) sags 1 µm into a wall of 3 mm radius, and a burr
                                    // held here slides on the bone it cuts by a few µm more
}

std::unique_ptr<ForbiddenRegion> ForbiddenRegion::Make(uint32_t id, std::string name, const TriangleMesh& structure,
                                                       double margin, std::string& error) {
  auto field = std::make_shared<MeshSignedDistance>();
  std::string why;
  if (!field->Build(structure, why)) {
    error = "forbidden region '" + name + "': the structure must be a closed surface (" + why + ")";
    return nullptr;
  }
  return Make(id, std::move(name), std::move(field), margin, error);
}

std::unique_ptr<ForbiddenRegion> ForbiddenRegion::Make(uint32_t id, std::string name,
                                                       std::shared_ptr<const MeshSignedDistance> structure, double margin,
                                                       std::string& error) {
  if (!(margin >= 0) || !std::isfinite(margin)) {
    error = "forbidden region '" + name + "': the margin must be a number ≥ 0 mm";
    return nullptr;
  }
  if (!structure || structure->Empty()) {
    error = "forbidden region '" + name + "': the structure has no closed surface";
    return nullptr;
  }
  std::unique_ptr<ForbiddenRegion> f(new ForbiddenRegion(id, std::move(name), margin));
  f->Distance = std::move(structure);
  return f;
}

bool ForbiddenRegion::Measure(const Vec3& p, double reach, FixtureMemory& m, double& distance,
                              Vec3& normal) const noexcept {
  Vec3 closest;
  double d = 0;
  m.DistancePoint = p;
  if (!this->Distance->SignedDistance(p, reach, d, closest)) {
    m.Distance = distance = reach;  // a lower bound: the structure is farther
    return false;
  }
  m.Distance = distance = d;
  const Vec3 away = p - closest;
  const double length = Norm(away);
  // The distance field's gradient: away from the surface outside, towards it inside.
  normal = length > 1e-12 ? away * ((d >= 0 ? 1.0 : -1.0) / length) : m.ContactNormal;
  return true;
}

bool ForbiddenRegion::Allowed(const FixtureTuning& t, const Vec3& p, double radius, FixtureMemory& m) const noexcept {
  (void)t;
  double d;
  Vec3 n;
  this->Measure(p, HUGE_VAL, m, d, n);
  return d >= this->SafetyMargin + radius;
}

bool ForbiddenRegion::Advance(const Vec3& from, const Vec3& to, double clearance, FixtureMemory& m, Vec3& at,
                              Vec3& normal) const noexcept {
  const double length = Norm(to - from);
  if (!(length > 0)) return false;
  const Vec3 unit = (to - from) / length;
  double travelled = 0;
  Vec3 x = from;
  at = from;
  for (int step = 0; step < AdvanceSteps; ++step) {
    double d;
    Vec3 n;
    this->Measure(x, clearance + (length - travelled) + 1.0, m, d, n);
    const double free = d - clearance;  // no point of the region is nearer than this
    at = x;
    normal = n;
    if (free >= length - travelled) return false;
    if (free < Gap) return true;
    travelled += free;
    x = from + unit * travelled;
  }
  return false;  // not proven blocked in the steps (`at`: the last point proven free): the ends decide
}

Vec3 ForbiddenRegion::Constrain(const FixtureTuning& t, const Vec3& from, const Vec3& to, double radius,
                                FixtureMemory& m) const noexcept {
  const double clearance = this->SafetyMargin + radius;
  const double move = Norm(to - from);
  // Far away: the last measured distance bounds this one (|∇d| = 1), no query.
  if (!m.Contact && m.Distance - Norm(to - m.DistancePoint) - clearance > move + t.Capture) return to;
  double d;
  Vec3 n;
  const bool near = this->Measure(to, clearance + move + t.Capture + 1.0, m, d, n);
  const bool inside = near && d < clearance;
  if (m.Contact) {
    const Vec3 at = this->Slide(from, inside ? to + n * (clearance - d + SlideGap) : to, inside ? n : m.ContactNormal,
                                clearance, m);
    m.Contact = m.Contact || inside;  // pressing on the wall
    return at;
  }
  Vec3 at, normal;
  if (!inside) {
    if (!this->Advance(from, to, clearance, m, at, normal)) return to;
    m.Contact = true;  // a chord through the region: stopped where it starts
    m.ContactNormal = normal;
    return at + normal * SlideGap;
  }
  this->Advance(from, to, clearance, m, at, normal);  // first contact (short of the wall when its steps ran out)
  m.Contact = true;
  m.ContactNormal = normal;
  return at + normal * SlideGap;
}

// From where the tool is towards `goal` (the tool projected onto the wall, or the tool itself when
// it is off the wall again) in short steps, each put back onto the wall when it went in: the
// straight way between two far points of a curved wall would cut through it. Never to the region's
// far side (the hand pushed past its middle) nor into another part of it. In contact while the
// last step had to be put back.
Vec3 ForbiddenRegion::Slide(const Vec3& from, const Vec3& goal, const Vec3& goalNormal, double clearance,
                            FixtureMemory& m) const noexcept {
  if (Dot(goalNormal, m.ContactNormal) < 0) return from;
  Vec3 at = from, normal = m.ContactNormal;
  bool pushed = true;
  for (int step = 0; step < SlideSteps; ++step) {
    const Vec3 ahead = goal - at;
    const double length = Norm(ahead);
    if (length < 1e-9) break;
    const Vec3 next = length > SlideStep ? at + ahead * (SlideStep / length) : goal;
    double dn;
    Vec3 nn;
    if (!this->Measure(next, clearance + 2 * SlideStep, m, dn, nn) || dn >= clearance + SlideGap) {
      at = next;  // off the wall: a free step
      pushed = false;
      continue;
    }
    if (Dot(nn, normal) < 0) break;
    const Vec3 onWall = next + nn * (clearance + SlideGap - dn);
    double check;
    Vec3 checkNormal;
    if (this->Measure(onWall, clearance + 1.0, m, check, checkNormal) && check < clearance) break;  // another part of it
    at = onWall;
    normal = nn;
    pushed = true;
  }
  m.Contact = pushed;
  m.ContactNormal = normal;
  return at;
}

void ForbiddenRegion::Evaluate(const FixtureTuning& t, const FixtureTool& tool, const Vec3& goal, double dt,
                               FixtureMemory& m, FixtureForce& out) const noexcept {
  const Vec3 tipVelocity = m.HasLast && dt > 0 ? (tool.Tip - m.LastTip) / dt : Vec3{};
  WallContactForce(t, tool, goal, dt, m, out);
  if (m.Contact || !m.Armed || !(t.Capture > 0) || !(t.Damping > 0)) return;
  // The approach band: damping on the velocity towards the wall, fading to none at the band's edge.
  const double clearance = this->SafetyMargin + tool.Radius;
  if (m.Distance - Norm(goal - m.DistancePoint) - clearance >= t.Capture) return;
  double d;
  Vec3 n;
  if (!this->Measure(goal, clearance + t.Capture, m, d, n)) return;
  const double gap = d - clearance;
  const double approach = Dot(tipVelocity, n);
  if (gap >= t.Capture || approach >= 0) return;
  const double share = std::clamp(1.0 - gap / t.Capture, 0.0, 1.0);
  out.Damper = n * (-t.Damping * share * approach);
}

}  // namespace rp
