#pragma once
// The force of the burr on the hand (seed eq. 1–6), with the Haptics module's stability pieces:
//     F = k (x_anchor − x_hip) + b (v_proxy − v_hip)                       (eq. 1–3)
// k, b of the material resisting the push (materials.json), scaled into the device's passive
// region (Colgate–Schenkel, rpStability: the budget left by other contacts is shared), then the
// passivity observer/controller (Hannaford & Ryu) over each contact episode, then the clamp of
// eq. 6 that keeps the direction. x_anchor is the proxy moved onto the bone surface along the
// contact normal (rpBurrProxy), so on a flat face F = k·d along the face normal exactly.
// Virtual fixtures (rpToolConstraint.h) add their force before the passivity observer and the clamp.
// Not thread-aware: the servo task owns one. Update() never allocates.
#include "rpBurrProxy.h"
#include "rpHapticDevice.h"
#include "rpPassivityObserver.h"
#include "rpStability.h"
#include "rpToolConstraint.h"

namespace rp {

struct BurrForceOptions {
  bool LimitGains = true;
  bool PassivityControl = true;
  double Period = 0.001;        // s
  double WorkspaceScale = 1.0;  // scene mm per device mm
};

struct BurrForce {
  Vec3 Hip, Proxy, Anchor;
  Vec3 Goal;            // where the constraints' walls let the burr's centre go (= Hip when free): the burr cuts towards it
  Vec3 Force;           // on the hand, after limits, passivity and the clamp (N, scene frame)
  Vec3 UnclampedForce;  // before the clamp
  bool Clamped = false;
  double Depth = 0;     // |anchor − HIP| along the contact normal (mm)
  double Stiffness = 0; // rendered k (N/mm) after the gain limit
  GainLimits Gains;
  ConstraintForce Constraint;  // what the virtual fixtures added (included in Force); ForbidCut
  double ObservedEnergy = 0, AddedDamping = 0;
  BurrContact Contact;
};

class BurrRenderer {
 public:
  BurrRenderer();
  void SetDevice(const DeviceInfo& device);
  const DeviceInfo& Device() const { return this->DeviceLimits; }
  void SetOptions(const BurrForceOptions& options) { this->Options = options; }
  const BurrForceOptions& GetOptions() const { return this->Options; }
  /// Puts the proxy on the HIP (no contact).
  void Reset(const Vec3& hip) noexcept;
  /// One servo tick for burr centre `hip` (scene frame). `otherStiffness`/`otherDamping` are the
  /// summed gains other contacts (the mesh god-object) already render this tick: the passive
  /// budget is shared with them.
  /// `elapsed` is the measured time since the previous tick (a servo stall shows there): the
  /// velocities of the damping term use it; 0 means one period.
  /// `constraints` (virtual fixtures, rpToolConstraint.h) first hold the burr's centre back
  /// (walls: the burr meets the bone, and cuts, where they let it go), then act on it beside the
  /// bone's contact, inside the passivity observer and the clamp; `stylus` is the drill's pose.
  const BurrForce& Update(const DrillVolume& volume, const Vec3& hip, double radius, double otherStiffness = 0,
                          double otherDamping = 0, double elapsed = 0, ToolConstraints* constraints = nullptr,
                          const Pose& stylus = Pose{}) noexcept;
  const BurrForce& Output() const { return this->Out; }
  BurrProxy& Proxy() { return this->God; }

 private:
  BurrForceOptions Options;
  DeviceInfo DeviceLimits;
  BurrProxy God;
  PassivityObserver Observer;
  Vec3 LastHip, LastHeld, LastProxy;
  bool Initialized = false;
  bool WasInContact = false;
  BurrForce Out;
};

}  // namespace rp
