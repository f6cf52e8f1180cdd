#include "rpSurfaceConstraint.h"

#include <cmath>

namespace rp {

std::unique_ptr<SurfaceConstraint> SurfaceConstraint::Plane(uint32_t id, std::string name, const Vec3& point,
                                                            const Vec3& normal) {
  std::unique_ptr<SurfaceConstraint> s(new SurfaceConstraint(id, std::move(name), Shape::Plane));
  s->Point = point;
  s->Normal = Normalized(normal);
  return s;
}

std::unique_ptr<SurfaceConstraint> SurfaceConstraint::Sphere(uint32_t id, std::string name, const Vec3& center,
                                                             double radius) {
  std::unique_ptr<SurfaceConstraint> s(new SurfaceConstraint(id, std::move(name), Shape::Sphere));
  s->Point = center;
  s->Radius = radius;
  return s;
}

std::unique_ptr<SurfaceConstraint> SurfaceConstraint::Mesh(uint32_t id, std::string name, const TriangleMesh& mesh,
                                                           std::string& error) {
  if (!mesh.Validate(error)) return nullptr;
  if (mesh.NumberOfTriangles() == 0) {
    error = "surface constraint '" + name + "': the model has no triangles";
    return nullptr;
  }
  std::unique_ptr<SurfaceConstraint> s(new SurfaceConstraint(id, std::move(name), Shape::Mesh));
  s->Tree.Build(mesh);
  if (s->Tree.Empty()) {
    error = "surface constraint '" + s->Name() + "': the model has only degenerate triangles";
    return nullptr;
  }
  return s;
}

bool SurfaceConstraint::Closest(const Vec3& p, double maxDistance, Vec3& point, double& distance) const noexcept {
  switch (this->Form) {
    case Shape::Plane: {
      const double signedDistance = Dot(p - this->Point, this->Normal);
      point = p - this->Normal * signedDistance;
      distance = std::fabs(signedDistance);
      break;
    }
    case Shape::Sphere: {
      const Vec3 out = p - this->Point;
      const double r = Norm(out);
      // At the centre every surface point is closest: any will do.
      point = this->Point + (r > 0 ? out * (this->Radius / r) : Vec3{this->Radius, 0, 0});
      distance = std::fabs(r - this->Radius);
      break;
    }
    case Shape::Mesh: {
      ClosestPointHit hit;
      if (!this->Tree.ClosestPoint(p, maxDistance, hit)) return false;
      point = hit.Point;
      distance = std::sqrt(hit.Distance2);
      break;
    }
  }
  return distance <= maxDistance;
}

void SurfaceConstraint::Evaluate(const FixtureTuning& t, const FixtureTool& tool, const Vec3& goal, double dt,
                                 FixtureMemory& m, FixtureForce& out) const noexcept {
  (void)goal;
  out = FixtureForce{};
  // While the force still fades out after a release, keep following the surface.
  const double reach = m.Engaged || m.Weight > 0 ? HUGE_VAL : t.Capture;
  Vec3 point;
  double distance = HUGE_VAL;
  const bool found = this->Closest(tool.Tip, reach, point, distance);
  m.Distance = found ? distance : HUGE_VAL;
  m.Engaged = found && distance <= (m.Engaged ? t.Release : t.Capture);
  if (!found) {
    m.HasLast = false;
    return;
  }
  m.Proxy = point;
  const Vec3 stretch = point - tool.Tip;
  const Vec3 relative = m.HasLast && dt > 0 ? ((point - m.LastProxy) - (tool.Tip - m.LastTip)) / dt : Vec3{};
  out.Spring = stretch * t.Stiffness;
  out.Damper = relative * t.Damping;
  out.Stiffness = t.Stiffness;
  out.Direction = Norm2(stretch) > 0 ? Normalized(stretch) : m.SpringDirection;
  out.Stored = 0.5 * t.Stiffness * Norm2(stretch);
  out.Engaged = m.Engaged;
  m.LastProxy = point;
  m.LastTip = tool.Tip;
  m.HasLast = true;
}

}  // namespace rp
