#pragma once
// The haptic servo task (runs inside rp::ServoLoop at 1 kHz): reads the tool in the scene frame
// (rpToolInput: a device through HapticDeviceToRAS, or a pose already in RAS such as a tracked
// stylus), renders the force (contacts and virtual fixtures, rpToolConstraint), ramps it in on
// start, and a watchdog zeroes it when a tick overran or the device reported an error. It
// publishes its state for the main thread (LatestValue) and log records for a writer thread
// (SPSC ring). It never touches a scene node, never allocates, locks or logs in Tick().
#include <algorithm>
#include <atomic>

#include "rpFixtureRenderer.h"
#include "rpHapticRenderer.h"
#include "rpLatestValue.h"
#include "rpServoLoop.h"
#include "rpSpscRing.h"
#include "rpToolInput.h"

namespace rp {

/// The time a servo task keeps (servo thread only): the measured time since the previous tick
/// (a stall, the thread not run, shows as more than one period) and the force ramp that starts
/// the force again after a start or a watchdog trip. Shared by every haptic servo task.
struct ServoClock {
  double RampStart = 0, LastTime = 0;
  /// Seconds since the previous tick (`fallback` when the clock did not advance). On the first
  /// tick (`first`) it is one period, and the ramp starts.
  double Elapsed(const TickInfo& tick, bool first, double fallback) noexcept {
    if (first) {
      this->RampStart = tick.Time;
      this->LastTime = tick.Time - tick.Period;
    }
    const double elapsed = tick.Time > this->LastTime ? tick.Time - this->LastTime : fallback;
    this->LastTime = tick.Time;
    return elapsed;
  }
  void RestartRamp(double time) noexcept { this->RampStart = time; }
  /// The force's scale at `time`: 0 → 1 over `seconds` since the ramp started (1 when 0 s).
  double Ramp(double time, double seconds) const noexcept {
    return seconds > 0 ? std::min(1.0, (time - this->RampStart) / seconds) : 1.0;
  }
};

/// What the main thread shows at display rate (copied into nodes by the scene bridge).
struct HapticState {
  double Time = 0;
  uint64_t Tick = 0;
  Vec3 Hip, Proxy, Force;  // tip, scene frame; force in N on the hand
  Pose Stylus;             // stylus pose in the scene
  int32_t Contacts = 0;
  int32_t Label = -1;      // material index of the deepest contact, -1 none
  double RampScale = 0;
  uint32_t WatchdogTrips = 0;
  bool DeviceError = false;
  bool Clamped = false;
  double ObservedEnergy = 0;
  double StiffnessScale = 1;
  double Elapsed = 0;         // s since the previous tick (a stall shows here)
  uint32_t Stalls = 0;        // ticks that came more than 1.5 periods after the previous one
  bool StallLimited = false;  // this tick's force was held to what the motion justifies
  uint32_t Buttons = 0;
  int32_t NumberOfPoints = 0;
  Vec3 Hips[MaxToolPoints], Proxies[MaxToolPoints];
  FixtureStatus Fixtures;  // the plan's virtual fixtures this tick (none when Count is 0)
};

/// One line of the session log.
struct HapticLogRecord {
  double Time = 0;
  Vec3 Hip, Proxy, Force;
  int32_t Label = -1;
  int32_t Contacts = 0;
  float TickComputeUs = 0;  // the previous tick's compute time
  float Elapsed = 0;        // s since the previous tick (a stall shows here)
  double ObservedEnergy = 0;  // passivity observer, N·mm (mJ): ≥ 0 while no energy was injected
  uint32_t Flags = 0;       // 1: watchdog tripped, 2: clamped, 4: held after a stall
};
using HapticLogRing = SpscRing<HapticLogRecord, 8192>;

class HapticServo : public ServoTask {
 public:
  explicit HapticServo(HapticDevice& device);

  /// Configure while stopped.
  HapticRenderer& Renderer() { return this->Render; }
  void SetRampSeconds(double seconds) { this->RampSeconds = seconds; }
  void EnableLog(bool enable) { this->LogEnabled.store(enable); }

  /// Any time, from the owner thread.
  SceneExchange& Scenes() { return this->SceneSlots; }
  /// The virtual fixtures evaluated beside the contacts (rpToolConstraint.h); none by default.
  ConstraintExchange& Constraints() { return this->ConstraintSlots; }
  /// The tool in the scene frame: HapticDeviceToRAS (SetDeviceToScene), or poses in RAS already.
  ToolInput& Input() { return this->Tool; }
  /// The servo period the passivity limits assume (s): the measured one when it is longer
  /// than the nominal period (Colgate-Schenkel's T). ≤ 0: the nominal period.
  void SetStabilityPeriod(double seconds) { this->StabilityPeriod.store(seconds, std::memory_order_relaxed); }
  /// Latest published state; false when no tick ran yet.
  bool ReadState(HapticState& state) const { return this->State.Read(state) != 0; }
  HapticLogRing& LogRing() { return this->Log; }

  void ServoStarted() noexcept override;
  void Tick(const TickInfo& tick) noexcept override;
  void ServoStopping() noexcept override;

 private:
  ToolInput Tool;
  HapticRenderer Render;
  SceneExchange SceneSlots;
  ConstraintExchange ConstraintSlots;
  LatestValue<HapticState> State;
  HapticLogRing Log;
  std::atomic<bool> LogEnabled{false};
  std::atomic<double> StabilityPeriod{0};
  double RampSeconds = 0.5;
  // Servo thread only:
  ServoClock Clock;
  bool First = true;
  uint32_t Trips = 0, Stalls = 0;
  HapticState Scratch;
};

}  // namespace rp
