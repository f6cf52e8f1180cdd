#pragma once
// Forbidden region: a structure at risk (a closed surface) plus its safety margin is a wall the
// tool cannot enter: the tool's surface (a burr of radius r, a stylus tip of radius 0) stays at
// least margin + r from the structure. The tool's proxy is a god-object on the offset surface
// {signed distance = margin + r}:
//   - a move from outside is advanced conservatively along the segment (each step the distance to
//     the offset surface, which no part of the region can be nearer than: Lipschitz), so the first
//     contact is found at any speed;
//   - pressing on, the proxy slides from where the tool is towards the tool projected onto the
//     offset surface (along the distance field's gradient), in short steps each put back onto
//     the wall, so the tool's own path hugs the wall (never the region's far side);
//   - before the wall, within the capture band, the approach is damped (slowing the hand, no force
//     at rest, none at the band's edge).
// Far from the structure the last distance bounds the next (Lipschitz) and no query is made.
#include <memory>

#include "rpMeshSignedDistance.h"
#include "rpVirtualFixture.h"

namespace rp {

class ForbiddenRegion : public VirtualFixture {
 public:
  /// The structure must be a closed surface (its inside is forbidden too). nullptr with `error`.
  static std::unique_ptr<ForbiddenRegion> Make(uint32_t id, std::string name, const TriangleMesh& structure, double margin,
                                               std::string& error);
  /// The same sharing a signed distance already built (a plan snapshot's structure at risk).
  static std::unique_ptr<ForbiddenRegion> Make(uint32_t id, std::string name,
                                               std::shared_ptr<const MeshSignedDistance> structure, double margin,
                                               std::string& error);
  double Margin() const { return this->SafetyMargin; }
  const MeshSignedDistance& Field() const { return *this->Distance; }

  Vec3 Constrain(const FixtureTuning& tuning, const Vec3& from, const Vec3& to, double radius,
                 FixtureMemory& memory) const noexcept override;
  bool Allowed(const FixtureTuning& tuning, const Vec3& p, double radius, FixtureMemory& memory) const noexcept override;
  void Evaluate(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& memory,
                FixtureForce& out) const noexcept override;

  /// The proxy keeps this gap (mm) outside the offset surface.
  static constexpr double Gap = 1e-4;

 private:
  ForbiddenRegion(uint32_t id, std::string name, double margin)
      : VirtualFixture(FixtureKind::ForbiddenRegion, id, std::move(name)), SafetyMargin(margin) {}
  /// Signed distance at `p` (and the outward normal there), remembered for the Lipschitz bound;
  /// false when the structure is farther than `reach` (then `distance` is that lower bound).
  bool Measure(const Vec3& p, double reach, FixtureMemory& m, double& distance, Vec3& normal) const noexcept;
  /// Advances from `from` (outside) towards `to` until the offset surface at `clearance`: true at a
  /// contact (`at`, `normal`); false when the move is free or its steps ran out (`at`: the last
  /// point proven outside).
  bool Advance(const Vec3& from, const Vec3& to, double clearance, FixtureMemory& m, Vec3& at,
               Vec3& normal) const noexcept;

  Vec3 Slide(const Vec3& from, const Vec3& goal, const Vec3& goalNormal, double clearance, FixtureMemory& m) const noexcept;

  double SafetyMargin = 0;
  std::shared_ptr<const MeshSignedDistance> Distance;
};

}  // namespace rp
