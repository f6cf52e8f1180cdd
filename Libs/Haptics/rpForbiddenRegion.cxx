#include "rpForbiddenRegion.h"

#include <algorithm>
#include <cmath>

namespace rp {

namespace {
constexpr int AdvanceSteps = 12;  // conservative-advancement steps per move (each one BVH query)
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
  if (!near || d >= clearance) {
    if (m.Contact) {  // released (the tool came off the wall)
      m.Contact = false;
      return to;
    }
    Vec3 at, normal;
    if (!this->Advance(from, to, clearance, m, at, normal)) return to;
    m.Contact = true;  // a chord through the region: stopped where it starts
    m.ContactNormal = normal;
    return at + normal * Gap;
  }
  if (!m.Contact) {  // first contact: where the move meets the wall
    Vec3 at, normal;
    this->Advance(from, to, clearance, m, at, normal);  // short of the wall when its steps ran out: stop there
    m.Contact = true;
    m.ContactNormal = normal;
    return at;
  }
  // Sliding: `to` onto the offset surface along the gradient, unless that lands on the far side
  // (the hand pushed past the region's middle) or inside another part of the region.
  if (Dot(n, m.ContactNormal) < 0) return from;
  const Vec3 onWall = to + n * (clearance - d + Gap);
  double check;
  Vec3 checkNormal;
  const Vec3 keep = m.ContactNormal;
  if (this->Measure(onWall, clearance + 1.0, m, check, checkNormal) && check < clearance) {
    m.ContactNormal = keep;
    return from;
  }
  m.ContactNormal = n;
  return onWall;
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
