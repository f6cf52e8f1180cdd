#pragma once
// The drilling servo task (inside rp::ServoLoop at 1 kHz, or ticked by hand for scripted runs):
// tool in RAS (rpToolInput: a device through HapticDeviceToRAS, or a pose already in RAS such as
// a tracked drill) → burr god-object and force (rpBurrRenderer, with the virtual fixtures of
// rpToolConstraint) → cut (rpBoneCutter, unless a fixture forbids it) → force to the device,
// summed with the mesh god-object of the scene's other haptic models and clamped (eq. 6).
//
// Cutting: while the burr is on and presses on bone, the bone ahead of it recedes at
//     v = FeedRate · (|F| / Fmax) · (rpm / ReferenceRpm) / hardness        (mm/s)
// (hardness: the mean of the bone ahead of the burr, weighted by how much of it the burr touches)
// (removal proportional to the contact force, the burr speed and 1/hardness, as in Archard's
// wear law); the burr's sphere is carved v·dt·CutSlices further towards the hand than the last
// cut, a share of its rows each tick over CutSlices ticks (so no tick carries a whole cut: the
// carving lags the hand by CutSlices ms, 0.008 mm at 2 mm/s), and the proxy follows (within
// rpBurrProxy::Skin).
// A cut that reaches a protected voxel is refused: the burr stops (latched until it is switched
// off and on again) and the state says so. A stroke is one burr-on period; Undo restores the
// last stroke, Reset the bone as built (both a few hundred blocks per tick).
//
// Threads: the owner configures while stopped; Control() and the requests come from the main
// thread; state (LatestValue) and the path record (SPSC ring) go out to it. Tick() never
// allocates, locks or logs.
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>

#include "rpBoneCutter.h"
#include "rpBurrRenderer.h"
#include "rpHapticServo.h"

namespace rp {

/// What the main thread sets at any time.
struct DrillControl {
  bool BurrOn = false;
  double Radius = 2.0;      // mm (1–3 for the usual burrs)
  double Rpm = 60000;       // burr speed
};

struct DrillServoOptions {
  double FeedRate = 2.0;          // mm/s into hardness-1 bone at the device's maximum force and ReferenceRpm
  double ReferenceRpm = 60000;
  double WarningDistance = 2.0;   // mm from the burr's surface to a protected structure
  double RampSeconds = 0.2;       // force ramp after start or a watchdog trip
  int CutSlices = 4;              // one advance's carving is spread over this many ticks (a share each)
  Vec3 BurrCenter;                // burr centre in the stylus frame (mm): the tool tip
};

/// The state the main thread shows (copied at display rate).
struct DrillState {
  double Time = 0;
  uint64_t Tick = 0;
  Vec3 Hip, Proxy, Force;                // burr centre (device), burr centre (proxy), force on the hand (N)
  double Radius = 0;
  bool BurrOn = false, Contact = false, Cutting = false, Embedded = false, Clamped = false;
  bool Restoring = false, Stopped = false, Warning = false, DeviceError = false;
  int32_t Material = -1;                 // 0-based material resisting the burr, −1 none
  int32_t CutMaterial = -1;              // 0-based material being cut, −1 none
  double Depth = 0;                      // mm the hand is beyond the bone surface
  double FeedMmPerS = 0;                 // current cutting speed
  double RemovedMm3[DrillVolume::MaxMaterials] = {};
  double RemovedTotalMm3 = 0;
  double ProtectedDistance = std::numeric_limits<double>::infinity();  // burr surface to protected (mm)
  double ClosestApproach = std::numeric_limits<double>::infinity();    // smallest so far
  uint64_t RefusedTicks = 0;             // cuts refused at a protected voxel
  int32_t UndoableStrokes = 0;
  uint32_t Strokes = 0;
  bool LastStrokeLost = false;
  uint32_t WatchdogTrips = 0;
  double ObservedEnergy = 0, Stiffness = 0, RampScale = 0;
  double PeakForce = 0;                  // largest |F| sent so far (N)
  FixtureStatus Fixtures;                // the plan's virtual fixtures this tick (none when Count is 0)
};

/// One line of the drill path (flags: see DrillRecordFlags).
struct DrillRecord {
  double Time = 0;
  Vec3 Hip, Proxy, Force;
  float Radius = 0;
  float RemovedTotalMm3 = 0;
  float ProtectedDistance = 0;
  float TickComputeUs = 0;
  uint32_t Flags = 0;
  int32_t CutMaterial = -1;  // 0-based material the burr was cutting (or pressing on), −1 none
};
namespace DrillRecordFlags {
constexpr uint32_t BurrOn = 1, Contact = 2, Cutting = 4, Refused = 8, Clamped = 16, Embedded = 32, Watchdog = 64;
}
using DrillRecordRing = SpscRing<DrillRecord, 8192>;

class DrillServo : public ServoTask {
 public:
  DrillServo(HapticDevice& device, DrillVolume& volume, const DrillServoOptions& options = {});

  // ---- configure while stopped
  BurrRenderer& Burr() { return this->Render; }
  BoneCutter& Cutter() { return this->Cut; }
  /// The other haptic models (rendered by the Haptics module's god-object in the same tick).
  HapticRenderer& MeshRenderer() { return this->Mesh; }
  /// A protected structure's surface for the distance read-out (kept alive by the owner).
  void SetProtectedSurface(const BVH* tree) {
    this->Protected = tree;
    this->HasProtectedPoint = false;
  }
  const DrillServoOptions& Options() const { return this->Settings; }
  /// How far a cut can lead the proxy (mm): one cut's advance at the fastest feed (the hand at
  /// the device's maximum force, the softest material) over CutSlices ticks of `period` s. The
  /// carving reaches this much beyond the burr's sphere along its path.
  double MaxCutLead(double rpm, double period) const;
  /// Starts the burr at `center` (scene frame) as if it had been there, cutting: the proxy is
  /// placed there and, with the burr on, its sphere is carved (refused at protected voxels).
  /// For scripted runs that begin inside bone (`roboplan drill --from`). Not while running.
  void PlaceBurr(const Vec3& center, const DrillControl& control);

  // ---- any time, owner thread
  void SetControl(const DrillControl& control) { this->ControlValue.Publish(control); }
  void RequestUndo() { this->UndoRequests.fetch_add(1, std::memory_order_release); }
  void RequestReset() { this->ResetRequests.fetch_add(1, std::memory_order_release); }
  SceneExchange& Scenes() { return this->SceneSlots; }
  /// The virtual fixtures evaluated beside the bone's contact (rpToolConstraint.h); none by default.
  ConstraintExchange& Constraints() { return this->ConstraintSlots; }
  /// The tool in the scene frame: HapticDeviceToRAS (SetDeviceToScene), or poses in RAS already.
  ToolInput& Input() { return this->Tool; }
  bool ReadState(DrillState& state) const { return this->StateValue.Read(state) != 0; }
  DrillRecordRing& Records() { return this->Log; }
  void EnableRecords(bool enable) { this->Recording.store(enable, std::memory_order_relaxed); }

  void ServoStarted() noexcept override;
  void Tick(const TickInfo& tick) noexcept override;
  void ServoStopping() noexcept override;

 private:
  void Publish(const TickInfo& tick, uint32_t flags) noexcept;
  // Tick's parts (the servo thread's; none allocates, locks or logs).
  void ServeRequests() noexcept;
  bool CutAhead(const BurrForce& burr, const Vec3& hip, double radius, double rpm, double dt) noexcept;
  void MeasureProtected(const Vec3& proxy, double radius) noexcept;
  uint32_t FillState(const BurrForce& burr, const Vec3& hip, const Vec3& force, double radius, bool on, bool clamped,
                     bool refused, double ramp) noexcept;

  ToolInput Tool;
  DrillVolume& Volume;
  DrillServoOptions Settings;
  BurrRenderer Render;
  BoneCutter Cut;
  HapticRenderer Mesh;
  SceneExchange SceneSlots;
  ConstraintExchange ConstraintSlots;
  const BVH* Protected = nullptr;
  LatestValue<DrillControl> ControlValue;
  LatestValue<DrillState> StateValue;
  std::atomic<uint32_t> UndoRequests{0}, ResetRequests{0};
  std::atomic<bool> Recording{false};
  DrillRecordRing Log;
  // Servo thread only:
  uint32_t UndoSeen = 0, ResetSeen = 0;
  bool First = true, Placed = false, WasOn = false;
  bool HasProtectedPoint = false;
  Vec3 ProtectedPoint{};  // last tick's closest point on the protected surface
  Vec3 CutCenter;          // centre of the last cut; the next one advances from here
  bool HasCutCenter = false;
  Vec3 LastCut;            // centre of the last cut made (the bone around it is carved)
  double LastCutRadius = 0;
  bool HasLastCut = false;
  bool CutRemoved = false;  // the pending (sliced) cut has removed bone so far
  double CutFeed = 0;       // the feed that cut advanced at (mm/s)
  ServoClock Clock;
  uint32_t Trips = 0;
  DrillState Scratch;
};

}  // namespace rp
