#pragma once
// The seed paper's "constraint" mode (its section 2.2, OpenHaptics' HL_CONSTRAINT): once the tool
// comes within the capture distance of a surface, a proxy is held on the surface at the point
// closest to the tool, sliding along it as the tool moves, and a spring-damper pulls the hand to
// it; beyond the (larger) release distance it lets go (hysteresis: no chatter at the edge). The
// surface is a model's closed mesh (BVH closest point), a plane (a plan's cut plane) or a sphere
// (a spherical reaming shell), the last two exact.
#include <memory>

#include "rpBVH.h"
#include "rpVirtualFixture.h"

namespace rp {

class SurfaceConstraint : public VirtualFixture {
 public:
  static std::unique_ptr<SurfaceConstraint> Plane(uint32_t id, std::string name, const Vec3& point, const Vec3& normal);
  static std::unique_ptr<SurfaceConstraint> Sphere(uint32_t id, std::string name, const Vec3& center, double radius);
  /// nullptr with `error` for a mesh that does not validate or has no triangles.
  static std::unique_ptr<SurfaceConstraint> Mesh(uint32_t id, std::string name, const TriangleMesh& mesh,
                                                 std::string& error);

  /// The surface point closest to `p` within `maxDistance` (false when farther).
  bool Closest(const Vec3& p, double maxDistance, Vec3& point, double& distance) const noexcept;
  void Evaluate(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& memory,
                FixtureForce& out) const noexcept override;

 private:
  enum class Shape { Plane, Sphere, Mesh };
  SurfaceConstraint(uint32_t id, std::string name, Shape shape)
      : VirtualFixture(FixtureKind::SurfaceConstraint, id, std::move(name)), Form(shape) {}
  Shape Form;
  Vec3 Point, Normal;  // plane; sphere centre in Point
  double Radius = 0;
  BVH Tree;
};

}  // namespace rp
