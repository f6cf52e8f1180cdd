#pragma once
// Where virtual fixtures plug into the servo tick, haptics and drilling alike: plain C++
// constraints on the tool (a surface constraint, axis guidance, a depth stop, a forbidden region:
// one class each, built from plan nodes off the servo thread), evaluated every tick beside the
// tissue contact, inside the renderer's passivity observer and force clamp:
//
//   HapticRenderer::Update / BurrRenderer::Update (one servo tick, scene frame RAS)
//     0. constraints->Constrain(context, tip)                          → where the tool may be (walls:
//        a depth stop, a forbidden region hold the tool itself), and the gains they reserve
//     1. tissue contact with the tool there: proxies, spring-dampers, gain limits within the
//        budget the constraints left                                   → contact force, gains
//     2. constraints->Evaluate(context)   (this header)                → fixture force, gains, stored energy
//     3. passivity observer/controller over contact or fixture episodes (stored energy of both)
//     4. stall bound (contact + fixture stiffness), clamp (eq. 6)      → force to ToolInput::WriteForce
//   DrillServo::Tick then cuts towards where the constraints let the burr go, and only when no
//   constraint forbids it (ConstraintForce::ForbidCut).
//
// A set is built on the owner's thread and handed over whole (ConstraintExchange: HapticServo::
// Constraints(), DrillServo::Constraints(), no locks); once the servo thread acquired it, the set and
// its constraints are the servo thread's: a constraint may keep state (hysteresis, a held proxy),
// and CarryFrom() moves that state into the set that replaces it (the plan dragged in the viewer
// publishes a new set every frame). Evaluate() and CarryFrom() never allocate, lock or log.
#include <memory>
#include <vector>

#include "rpHandover.h"
#include "rpHapticDevice.h"

namespace rp {

struct FixtureOutput;  // rpFixtureRenderer.h

/// The tool as a constraint sees it in one servo tick (scene frame RAS, mm, s, N).
struct ConstraintContext {
  double Dt = 0.001;             // s since the previous tick (a stall shows here)
  double Period = 0.001;         // s, the period the gain limits assume
  Pose Stylus;                   // the tool's pose (orientation: a drill's or stylus's axis)
  Vec3 Tip;                      // the point the device holds: the haptic tip (HIP) or the burr's centre
  Vec3 TipVelocity;              // mm/s
  Vec3 Proxy;                    // where tissue contact holds the tool this tick (= Tip when free)
  /// Step 0: where the tool itself was last tick when it can lag the hand (a burr held by the
  /// bone it cuts): the walls' moves start there, so the tool's own path stays outside them.
  Vec3 From;
  bool HasFrom = false;
  double Radius = 0;             // the tool's radius (the burr's; 0 for a point)
  bool InContact = false;        // tissue contact this tick
  double ContactStiffness = 0;   // N/mm and N·s/mm the tissue contacts render at the device this tick
  double ContactDamping = 0;     // (GainLimits): the passive budget left is the device's less these
  const DeviceInfo* Device = nullptr;  // the device's limits (force, stiffness, damping)
  double WorkspaceScale = 1.0;   // scene mm per device mm
};

/// Where the constraints let the tool point go this tick, before the contact (step 0), and the
/// gains their springs will render (reserved first: the contacts get what the device has left).
struct ConstraintGoal {
  Vec3 Goal;                   // the tool point (= the tip when nothing holds it)
  double Stiffness = 0;        // N/mm, N·s/mm the constraints will render this tick
  double Damping = 0;
};

/// What the constraints add in one tick.
struct ConstraintForce {
  Vec3 Force;                  // N on the hand, scene frame
  Vec3 Torque;                 // N·mm (a tool's direction pulled to a plan's; devices with torque output)
  double Stiffness = 0;        // N/mm of the springs acting now (stall bound)
  double Damping = 0;          // N·s/mm
  double StoredEnergy = 0;     // N·mm the springs will give back (the passivity observer's U)
  bool Engaged = false;        // some constraint acts: a passivity episode runs
  bool ForbidCut = false;      // drilling: no bone may be removed this tick
  /// The plan's fixtures one by one this tick (FixtureConstraint; servo thread, valid during the
  /// tick): what the servo copies into the state it publishes (FixtureStatus). nullptr: none.
  const FixtureOutput* Fixtures = nullptr;
};

class ToolConstraint {
 public:
  virtual ~ToolConstraint() = default;
  /// Servo thread, before the contact: moves `goal` (the tip, or where the constraints before
  /// this one let it go) as far as this constraint allows, and adds the gains it reserves.
  /// Default: leaves it (a constraint that only adds a force).
  virtual void Constrain(const ConstraintContext& tool, ConstraintGoal& goal) noexcept { (void)tool, (void)goal; }  /// Servo thread: adds this constraint's force, gains and energy into `out` (which holds the
  /// constraints before it), sets Engaged / ForbidCut when it acts.
  virtual void Evaluate(const ConstraintContext& tool, ConstraintForce& out) noexcept = 0;
  /// Servo thread, when a new set replaces the one holding `previous` (same class, same place
  /// in the set): take its state over. Default: none.
  virtual void CarryFrom(const ToolConstraint& previous) noexcept { (void)previous; }
};

/// The constraints one servo evaluates (in the order added).
class ToolConstraints {
 public:
  /// Owner thread, before the set is published.
  void Add(std::unique_ptr<ToolConstraint> constraint) { this->Items.push_back(std::move(constraint)); }
  size_t Size() const { return this->Items.size(); }
  ToolConstraint& At(size_t i) const { return *this->Items[i]; }

  /// Servo thread, before the contact: where every constraint in turn lets the tool point go.
  ConstraintGoal Constrain(const ConstraintContext& tool) noexcept;
  /// Servo thread: every constraint's contribution summed (zero when the set is empty).
  ConstraintForce Evaluate(const ConstraintContext& tool) noexcept;
  /// Servo thread: constraint i takes over previous constraint i's state when both are the same class.
  void CarryFrom(const ToolConstraints& previous) noexcept;

 private:
  std::vector<std::unique_ptr<ToolConstraint>> Items;
};

/// Hands a set to the servo thread (Acquire with CarryFrom: see rpHandover.h).
using ConstraintExchange = Handover<ToolConstraints>;

/// Servo thread: the set to evaluate this tick, its state carried over at a swap.
inline ToolConstraints* AcquireConstraints(ConstraintExchange& exchange) noexcept {
  return exchange.Acquire([](ToolConstraints& next, const ToolConstraints& previous) noexcept { next.CarryFrom(previous); });
}

}  // namespace rp
