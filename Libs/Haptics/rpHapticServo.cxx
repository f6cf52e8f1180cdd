#include "rpHapticServo.h"

#include <algorithm>

namespace rp {
namespace {

// What every tick's log record holds (a trip's and a rendered tick's alike); the caller adds the rest.
HapticLogRecord LogRecordOf(const HapticState& s, const TickInfo& tick, double elapsed) noexcept {
  HapticLogRecord r;
  r.Time = tick.Time;
  r.Hip = s.Hip;
  r.Proxy = s.Proxy;
  r.TickComputeUs = static_cast<float>(tick.PreviousComputeNs * 1e-3);
  r.Elapsed = static_cast<float>(elapsed);
  return r;
}

}  // namespace

HapticServo::HapticServo(HapticDevice& device) : Tool(device) { this->Render.SetDevice(device.Info()); }

void HapticServo::ServoStarted() noexcept {
  this->First = true;
  this->Trips = 0;
  this->Stalls = 0;
  this->Tool.WriteForce(Vec3{});
}

void HapticServo::ServoStopping() noexcept { this->Tool.WriteForce(Vec3{}); }

void HapticServo::Tick(const TickInfo& tick) noexcept {
  HapticState& s = this->Scratch;
  s.Time = tick.Time;
  s.Tick = tick.Index;
  this->Render.SetScene(this->SceneSlots.Acquire());
  ToolConstraints* constraints = AcquireConstraints(this->ConstraintSlots);

  ToolSample tool;
  const bool ok = this->Tool.Read(tick.Time, tool);
  s.DeviceError = !ok;
  const double elapsed = this->Clock.Elapsed(tick, this->First, tick.Period);
  if (elapsed > 1.5 * tick.Period) ++this->Stalls;
  s.Elapsed = elapsed;
  s.Stalls = this->Stalls;
  // Watchdog: an overrun or a device error zeroes the force and restarts the ramp.
  if (!ok || tick.PreviousOverran) {
    ++this->Trips;
    this->Clock.RestartRamp(tick.Time);
    this->Tool.WriteForce(Vec3{});
    s.Force = Vec3{};
    s.RampScale = 0;
    s.WatchdogTrips = this->Trips;
    this->State.Publish(s);
    if (this->LogEnabled.load(std::memory_order_relaxed)) {
      HapticLogRecord r = LogRecordOf(s, tick, elapsed);
      r.Flags = 1;
      this->Log.TryPush(r);
    }
    return;
  }

  const Pose& stylus = tool.StylusToScene;

  RendererOptions options = this->Render.GetOptions();
  options.WorkspaceScale = this->Tool.WorkspaceScale();
  options.Period = std::max(tick.Period, this->StabilityPeriod.load(std::memory_order_relaxed));
  this->Render.SetOptions(options);
  if (this->First) {
    this->Render.Reset(stylus);
    this->First = false;
  }
  const RenderOutput& out = this->Render.Update(stylus, elapsed, constraints);
  const double ramp = this->Clock.Ramp(tick.Time, this->RampSeconds);
  const Vec3 force = out.Force * ramp;
  this->Tool.WriteForce(force);

  s.Hip = out.Points[0].Hip;
  s.Proxy = out.Points[0].Proxy;
  s.Force = force;
  s.Stylus = stylus;
  s.Contacts = out.Contacts;
  s.Label = out.PrimaryPoint >= 0 ? out.Points[out.PrimaryPoint].Label : -1;
  s.RampScale = ramp;
  s.WatchdogTrips = this->Trips;
  s.Clamped = out.Clamped;
  s.ObservedEnergy = out.ObservedEnergy;
  s.StiffnessScale = out.Gains.StiffnessScale;
  s.StallLimited = out.StallLimited;
  s.Buttons = tool.Buttons;
  s.NumberOfPoints = out.NumberOfPoints;
  for (int i = 0; i < out.NumberOfPoints; ++i) {
    s.Hips[i] = out.Points[i].Hip;
    s.Proxies[i] = out.Points[i].Proxy;
  }
  s.Fixtures.CopyFrom(out.Constraint.Fixtures);
  this->State.Publish(s);
  if (this->LogEnabled.load(std::memory_order_relaxed)) {
    HapticLogRecord r = LogRecordOf(s, tick, elapsed);
    r.Force = force;
    r.Label = s.Label;
    r.Contacts = s.Contacts;
    r.ObservedEnergy = out.ObservedEnergy;
    r.Flags = (out.Clamped ? 2u : 0u) | (out.StallLimited ? 4u : 0u);
    this->Log.TryPush(r);
  }
}

}  // namespace rp
