#pragma once
// A god-object for a spherical burr on a drillable voxel bone (Zilles & Salisbury 1995, for a
// sphere on a sampled field): the proxy is the burr centre that follows the device's burr centre
// (the HIP) but never lets the burr's sphere enter bone. Every move is a swept-sphere test
// against the voxels (continuous: no pop-through of thin cortex at any hand speed); blocked
// moves slide on up to three constraint planes, as the mesh god-object does, unless the push
// lies inside the bone's static friction cone. Only the burr cutting material (rpBoneCutter)
// lets the proxy advance into bone.
//
// Contact is found with a point shell (McNeely, Puterbaugh & Troy 1999, for a voxel map): a fixed
// set of ShellPoints directions u spread evenly over the sphere (a Fibonacci lattice), sampled at
// p + r·u in the trilinearly interpolated density. Across the bone's two-voxel ramp the density
// is linear in the distance to the surface, so a sample of density ρ lies (ρ − ½)·2h inside the
// bone: its gap is (½ − ρ)·2h. The contact normal is the sum of the inward directions −u of the
// points within a quarter voxel of the bone, weighted by how deep they are; the sweep steps the
// points facing the move half a voxel at a time and interpolates the first crossing. The work
// per tick is the same for any burr and voxel size (a fixed number of samples), not the number
// of voxels on the burr's surface. For the force, the contact point is then refined along the
// normal by a least-squares plane through the ramp voxels around it, which is exact on planar
// bone at any orientation (the spring stretch is the burr's true depth).
// Update() never allocates or locks.
#include <cstdint>

#include "rpDrillVolume.h"

namespace rp {

struct BurrContact {
  bool InContact = false;   // the burr's surface touches bone (within a quarter voxel)
  bool Embedded = false;    // the burr centre was deep in bone (e.g. after an undo): released, no force, no cutting
  int Planes = 0;           // constraint planes used this tick
  int Voxels = 0;           // shell points touching the bone
  Vec3 Normal;              // contact normal, out of the bone (unit; zero when the touches cancel out)
  Vec3 Anchor;              // the proxy moved onto the bone surface along the normal: the spring's end
  bool Refined = false;     // Anchor comes from the plane fit (else Anchor = proxy)
  uint8_t Material = 0;     // 1-based material resisting the push (stiffest ahead), 0: none
  uint8_t CutMaterial = 0;  // 1-based material most of the bone ahead of the push is (what the burr cuts), 0: none
  double CutHardness = 0;   // mean hardness of the bone ahead of the push (weighted by contact)
};

class BurrProxy {
 public:
  /// Places the proxy (the burr centre) at `position`, no contact.
  void Reset(const Vec3& position) noexcept;
  /// Moves the proxy towards the HIP under the bone's constraints.
  const BurrContact& Update(const DrillVolume& volume, const Vec3& hip, double radius) noexcept;
  const Vec3& Position() const { return this->P; }
  const BurrContact& Contact() const { return this->State; }

  /// The burr may overlap bone by this skin (in voxels, five times the 1/255 density rounding),
  /// so the walls it carved (with its full radius) never block it through rounding. A proxy can
  /// therefore sit one skin beyond the centre of the last cut: rpDrillServo advances each cut
  /// from the last one, not from the proxy, so the burr cannot creep deeper tick after tick.
  static constexpr double Skin = 0.02;
  /// The band (in voxels) beyond the burr's surface counted as touching.
  static constexpr double TouchBand = 0.25;
  /// Overlap (in voxels) beyond which the burr counts as embedded.
  static constexpr double EmbeddedDepth = 0.75;
  /// Points of the shell: 0.36 mm apart on a 2 mm burr, 0.54 mm on a 3 mm one (any voxel size).
  static constexpr int ShellPoints = 384;
  /// The shell's unit directions (computed once, on first use: Reset() does it before any tick).
  static const Vec3* ShellDirections() noexcept;

  /// Fraction of the move from `from` to `to` the sphere can make before it touches bone (> 1:
  /// free). `startOverlap` gets the deepest overlap (mm) at `from`. `atFrom`, when given, holds
  /// the shell's densities at `from` (Touching's `shell`), which the sweep then does not sample again.
  static double Sweep(const DrillVolume& volume, const Vec3& from, const Vec3& to, double radius,
                      double& startOverlap, const double* atFrom = nullptr) noexcept;
  /// Contact normal, materials and touching voxels of the sphere at `p`; `push` is the direction
  /// the hand pushes (HIP − proxy). False when nothing touches. `shell`, when given, gets the
  /// density at each of the ShellPoints.
  static bool Touching(const DrillVolume& volume, const Vec3& p, double radius, const Vec3& push,
                       BurrContact& contact, double* shell = nullptr) noexcept;
  /// The signed distance (mm) from `p` to the bone surface along the fitted local plane near the
  /// contact point p − normal·radius; false when the ramp there does not fit a plane.
  static bool SurfaceDistance(const DrillVolume& volume, const Vec3& p, const Vec3& normal, double radius,
                              double& distance, Vec3& fittedNormal) noexcept;

 private:
  Vec3 P;
  BurrContact State;
};

}  // namespace rp
