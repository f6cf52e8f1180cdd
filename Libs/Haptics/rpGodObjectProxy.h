#pragma once
// A god-object (constrained proxy) for one haptic interface point (HIP), after Zilles &
// Salisbury 1995 and Ruspini et al. 1997. The proxy follows the HIP but never crosses a surface:
// every move is a segment tested against the BVH (continuous collision), so thin structures
// cannot be popped through at any hand speed. Up to three constraint planes per tick (edges,
// concave corners), static/dynamic friction cone, force shading from vertex normals.
// Update() never allocates.
#include <cstdint>

#include "rpHapticScene.h"

namespace rp {

struct ContactPlane {
  Vec3 Normal;  // face normal (unit, outward)
  Vec3 Point;   // a point on the plane
  uint32_t Triangle = 0;
};

struct ProxyState {
  Vec3 Proxy;
  bool InContact = false;
  int PlaneCount = 0;
  ContactPlane Planes[3];
  Vec3 ForceNormal;  // the normal the spring force is shaded with (unit)
  uint32_t Triangle = 0;
  uint16_t Label = 0;  // material index of the contacted triangle
  bool Sticking = false;  // inside the friction cone this tick: the proxy did not move
  bool Sliding = false;   // moving under dynamic friction (the dynamic cone decides sticking)
};

class GodObjectProxy {
 public:
  /// The proxy keeps this gap (mm) above the surfaces it touches, so it never starts a move on
  /// (or under) a triangle.
  static constexpr double Gap = 1e-4;

  /// Places the proxy at `position` (assumed outside every object), no contact.
  void Reset(const Vec3& position) noexcept;
  /// Moves the proxy towards `hip` under the scene's constraints; friction and shading as asked.
  const ProxyState& Update(const HapticScene& scene, const Vec3& hip, bool friction, bool forceShading) noexcept;
  const ProxyState& State() const { return this->Current; }

 private:
  /// Moves from `from` towards `goal` with up to three constraint planes; returns the end point.
  Vec3 Solve(const HapticScene& scene, const Vec3& from, const Vec3& goal, ContactPlane planes[3],
             int& planeCount) const noexcept;

  ProxyState Current;
};

}  // namespace rp
