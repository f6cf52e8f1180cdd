#pragma once
// The servo-thread side of the virtual fixtures: each tick, from the tool and the current
// FixtureSet snapshot,
//   1. the walls (depth stop, forbidden regions) move a god-object from where the tool was let go
//      last tick towards the tool, as far as they allow: the goal, where the tool may be;
//   2. every fixture gives its spring-damper force on the hand;
//   3. each force is faded in and out (a fixture switched on or off, a guide capturing or
//      releasing the tool, a new snapshot changing a fixture) so that such events change the force
//      by at most the device's MaxForceRate × period per tick; the fixtures' summed gains are kept
//      in the device's passive region (Colgate–Schenkel, as tissue contact).
// The host renderer (haptics, drilling) adds the force to the tissue's inside its passivity
// observer and the eq. 6 clamp, and moves the tool to the goal before touching tissue. Never
// allocates, locks or logs; a snapshot is never dereferenced after the servo moved on from it.
#include "rpFixtureSet.h"
#include "rpStability.h"

namespace rp {

/// One fixture this tick, for the state the main thread shows.
struct FixtureReport {
  uint32_t Id = 0;
  FixtureKind Kind = FixtureKind::AxisGuidance;
  bool Enabled = false, Engaged = false, Armed = false, Contact = false;
  double Weight = 0;
  /// Surface: to the surface; axis: from the axis; depth stop: to the target depth (negative
  /// beyond); forbidden region: the tool point's signed distance from the structure (last measured).
  double Distance = 0;
  Vec3 Force;  // delivered, N
};

struct FixtureOutput {
  Vec3 Goal;              // where the walls let the tool point go (the tool point itself when free)
  Vec3 Force;             // N on the hand: faded, within the fixtures' gain limit, plus what still fades out
  Vec3 Torque;            // N·mm (axis guidance with angular stiffness)
  double Stiffness = 0;   // N/mm the fixtures render this tick (their share of the device's passive budget)
  double Damping = 0;     // N·s/mm
  double Stored = 0;      // N·mm held in their springs (passivity)
  bool Active = false;    // some fixture acts this tick (a contact episode, for the passivity observer)
  bool Blocked = false;   // a wall holds the tool back (Goal is not the tool point)
  int Count = 0;
  FixtureReport Fixtures[MaxFixtures];
};

/// The fixtures' reports as a servo publishes them for the main thread (HapticState, DrillState:
/// which fixture acts, engaged or not, at what distance). Copied in the tick: no allocation.
struct FixtureStatus {
  int Count = 0;
  FixtureReport Fixtures[MaxFixtures];
  /// This tick's reports (nullptr: no fixtures).
  void CopyFrom(const FixtureOutput* output) noexcept {
    this->Count = output ? output->Count : 0;
    for (int i = 0; i < this->Count; ++i) this->Fixtures[i] = output->Fixtures[i];
  }
};

class FixtureRenderer {
 public:
  FixtureRenderer() { this->SetDevice(DeviceInfo{}); }
  /// Configure while stopped (copies the limits only).
  void SetDevice(const DeviceInfo& device);
  /// Forgets every fixture's memory; the goal starts at `tip` (walls arm when it is allowed).
  void Reset(const Vec3& tip) noexcept;
  /// One tick: Constrain then Render. `set` may be nullptr (no fixtures: the goal is the tool
  /// point, no force). `dt` the time since the previous tick (s), `period` the servo's (its event
  /// budget and gain limits).
  const FixtureOutput& Update(const FixtureSet* set, const FixtureTool& tool, double dt, double period,
                              double workspaceScale = 1.0) noexcept;
  /// Step 1 alone (before the tissue contact): adopts a new set, arms the walls and moves the
  /// goal; `stiffness`/`damping` get the gains the fixtures will render this tick (the contacts
  /// share what is left of the device's passive budget).
  const Vec3& Constrain(const FixtureSet* set, const FixtureTool& tool, double period, double workspaceScale,
                        double& stiffness, double& damping) noexcept;
  /// Steps 2–3 (Constrain first when it did not run this tick).
  const FixtureOutput& Render(const FixtureSet* set, const FixtureTool& tool, double dt, double period,
                              double workspaceScale = 1.0) noexcept;
  const FixtureOutput& Output() const { return this->Out; }

 private:
  void Adopt(const FixtureSet* set) noexcept;
  void Arm(const FixtureSet& set, const FixtureTool& tool) noexcept;
  Vec3 ConstrainWalls(const FixtureSet& set, const FixtureTool& tool) noexcept;
  /// The fixtures' summed gains within the device's limits (at full weight: fades do not move them).
  GainLimits Gains(const FixtureSet& set, const FixtureForce* forces, double period, double workspaceScale) const noexcept;
  void Fade(const FixtureSet& set, const FixtureForce* forces, double stiffnessScale, double dampingScale,
            double budget) noexcept;

  DeviceInfo Limits;  // numbers only (no name: copying a string could allocate)
  const FixtureSet* Current = nullptr;
  int CurrentCount = 0;
  FixtureMemory Memory[MaxFixtures];
  const VirtualFixture* Geometry[MaxFixtures] = {};  // compared, never dereferenced once replaced
  FixtureTuning Tunings[MaxFixtures];
  Vec3 Goal;
  bool Initialized = false;
  bool Constrained = false;  // Constrain ran this tick (Render clears it)
  Vec3 Residual;  // force of fixtures that left or changed, still fading out
  FixtureOutput Out;
};

}  // namespace rp
