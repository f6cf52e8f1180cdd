#pragma once
// Virtual fixtures: constraints from the plan that act on the tool beside the tissue contact, in
// the 1 kHz servo (Rosenberg 1993; Abbott & Okamura's forbidden-region and guidance fixtures for
// impedance devices). Two families:
//   - guides pull the hand with a spring towards a proxy on the fixture (the surface constraint,
//     the seed paper's "constraint" mode; axis guidance): force only, the tool goes where the hand
//     takes it;
//   - walls stop the tool itself (the depth stop; a forbidden region around a structure at risk):
//     a god-object proxy that a swept test keeps on the allowed side at any speed, the hand feeling
//     the spring between the proxy and itself (as tissue contact).
// A fixture is its geometry, immutable once built; a FixtureSet snapshot (rpFixtureSet.h) gives each
// its tuning and whether it is on, and shares the geometry between snapshots. The servo thread
// evaluates it with its own FixtureMemory; nothing here allocates, locks or logs.
#include <cstdint>
#include <limits>
#include <string>

#include "rpVec3.h"

namespace rp {

enum class FixtureKind : uint8_t { SurfaceConstraint, AxisGuidance, DepthStop, ForbiddenRegion };
/// "surface", "axis", "depth", "forbidden" (what `--fixtures` takes).
const char* FixtureKindName(FixtureKind kind);

/// How a fixture feels (what a user tunes). Units: N/mm, N·s/mm, mm.
struct FixtureTuning {
  double Stiffness = 0.5;        // the spring between the hand and the fixture's proxy
  double Damping = 0.0005;       // on the relative velocity along the spring
  double Capture = 2.0;          // surface: engages within this distance; axis: capture radius;
                                 // depth stop: the stop holds within this radius of the axis;
                                 // forbidden region: the band before the wall where approach is damped
  double Release = 3.0;          // surface, axis: lets go beyond this (≥ Capture: hysteresis, no chatter)
  double AngularStiffness = 0;   // axis guidance, devices with torque output: N·mm per radian
};

/// The tool as the servo sees it this tick (scene frame).
struct FixtureTool {
  FixtureTool() = default;
  FixtureTool(const Vec3& tip, const Vec3& direction, double radius, const Vec3& from = {}, bool hasFrom = false)
      : Tip(tip), Direction(direction), Radius(radius), From(from), HasFrom(hasFrom) {}
  Vec3 Tip;            // the tool point: a stylus tip, a burr centre
  Vec3 Direction;      // unit, the way the tool points (tip forward); zero when the device has no orientation
  double Radius = 0;   // a burr's radius (walls keep its surface, not its centre, off the forbidden region)
  Vec3 From;           // where the tool was last tick, when it can lag the hand (HasFrom)
  bool HasFrom = false;
};

/// What one fixture keeps between ticks (servo thread; FixtureRenderer holds one per fixture).
struct FixtureMemory {
  uint32_t Id = 0;
  bool Engaged = false;   // guides: within capture (with hysteresis); walls: pressed on this tick
  bool Armed = false;     // walls: the tool is on the allowed side (a wall switched on behind the tool waits for it)
  double Weight = 0;      // 0–1: the share of the force delivered (fades in and out at the device's event rate)
  Vec3 Proxy;             // guides: the point the spring pulls to
  Vec3 LastProxy, LastTip;
  bool HasLast = false;
  double Distance = std::numeric_limits<double>::infinity();  // last measured (see each fixture)
  Vec3 DistancePoint;     // where Distance was measured from (walls: for the Lipschitz bound)
  Vec3 Delivered;         // the force delivered last tick (N, after the weight)
  Vec3 SpringDirection;   // the last tick's FixtureForce::Direction and Across (the gains reserved
  bool SpringAcross = false;  // before the contact)
  bool Contact = false;   // walls: an active constraint plane this tick
  Vec3 ContactNormal;
};

/// One fixture's force this tick, before its fade weight.
struct FixtureForce {
  Vec3 Spring;            // N
  Vec3 Damper;            // N
  Vec3 Torque;            // N·mm (axis guidance with AngularStiffness)
  double Stiffness = 0;   // N/mm acting this tick (0 when no spring acts) ...
  Vec3 Direction;         // ... along this unit direction (a wall's normal, the pull to a surface),
  bool Across = false;    // or across it (axis guidance: every direction normal to the axis)
  double Stored = 0;      // ½ k |stretch|²: what the spring gives back (passivity)
  bool Engaged = false;   // see FixtureMemory::Engaged
};

class VirtualFixture {
 public:
  VirtualFixture(FixtureKind kind, uint32_t id, std::string name)
      : TheKind(kind), TheId(id), TheName(std::move(name)) {}
  virtual ~VirtualFixture() = default;
  VirtualFixture(const VirtualFixture&) = delete;
  VirtualFixture& operator=(const VirtualFixture&) = delete;

  FixtureKind Kind() const { return this->TheKind; }
  /// Stable across snapshots (a plan node's), so a new snapshot carries the fade on.
  uint32_t Id() const { return this->TheId; }
  const std::string& Name() const { return this->TheName; }
  bool IsWall() const { return this->TheKind == FixtureKind::DepthStop || this->TheKind == FixtureKind::ForbiddenRegion; }

  /// Walls: how far the tool point moving from `from` (allowed) towards `to` gets, sliding on the
  /// wall once it touches (memory.Contact, memory.ContactNormal say so). The move is tested as a
  /// whole, not at its ends, so no speed pops the tool through. Guides: `to`.
  virtual Vec3 Constrain(const FixtureTuning& tuning, const Vec3& from, const Vec3& to, double radius,
                         FixtureMemory& memory) const noexcept {
    (void)tuning, (void)from, (void)radius, (void)memory;
    return to;
  }
  /// Walls: whether the tool at `p` is on the allowed side (a wall arms only then).
  virtual bool Allowed(const FixtureTuning& tuning, const Vec3& p, double radius, FixtureMemory& memory) const noexcept {
    (void)tuning, (void)p, (void)radius, (void)memory;
    return true;
  }
  /// The force on the hand. `goal` is where the walls let the tool go this tick (the tip itself
  /// when nothing stops it); `dt` the time since the previous tick (s).
  virtual void Evaluate(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt,
                        FixtureMemory& memory, FixtureForce& out) const noexcept = 0;

 private:
  FixtureKind TheKind;
  uint32_t TheId;
  std::string TheName;
};

/// A wall's spring and damper from its constraint plane: the hand pressed past the proxy `goal`
/// along the wall's normal (what tissue contact gives, eq. 1–3). Shared by the walls.
void WallContactForce(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt,
                      FixtureMemory& memory, FixtureForce& out) noexcept;

}  // namespace rp
