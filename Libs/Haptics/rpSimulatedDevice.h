#pragma once
// A haptic device without hardware: the stylus follows a scripted trajectory (tests, benchmarks,
// the CLI) or a pose set interactively from the main thread (the viewer), and records the force
// it is asked to render. Usable wherever a HapticDevice is.
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "rpHapticDevice.h"
#include "rpLatestValue.h"
#include "rpSimulatedHand.h"

namespace rp {

/// Stylus motion over time in the device frame. Evaluate() must not allocate.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual void Evaluate(double time, Pose& pose, Vec3& velocity) const noexcept = 0;
  virtual double Duration() const = 0;
};

/// Piecewise-linear path through timed waypoints (constant orientation); holds the last
/// waypoint after the end.
class WaypointTrajectory : public Trajectory {
 public:
  /// Times must increase strictly. Returns false and names the problem.
  bool Set(const std::vector<double>& times, const std::vector<Vec3>& points, std::string& error);
  /// CSV "t,x,y,z" per line (s, mm; '#' comments and a non-numeric header allowed).
  bool LoadCSV(const std::string& path, std::string& error);
  void SetOrientation(const Pose& orientation) { this->Orientation = orientation; }
  void Evaluate(double time, Pose& pose, Vec3& velocity) const noexcept override;
  double Duration() const override { return this->Times.empty() ? 0.0 : this->Times.back(); }
  const std::vector<Vec3>& Points() const { return this->Positions; }

  /// From `a` to `b` at constant speed (mm/s), starting after `start` seconds at `a`.
  static std::shared_ptr<WaypointTrajectory> Line(const Vec3& a, const Vec3& b, double speed, double start = 0);

 private:
  std::vector<double> Times;
  std::vector<Vec3> Positions;
  Pose Orientation;
};

class SimulatedDevice : public HapticDevice {
 public:
  /// The default profile's limits (DeviceProfiles().front(): the seed paper's Phantom Omni).
  static DeviceInfo DefaultInfo();
  explicit SimulatedDevice(DeviceInfo info = DefaultInfo());

  bool Open(std::string& error) override;
  void Close() override { this->IsOpen = false; }
  const DeviceInfo& Info() const override { return this->Description; }
  bool Read(double time, DeviceState& state) noexcept override;
  void WriteForce(const Vec3& force) noexcept override;

  /// Scripted motion (set while the servo loop is stopped). nullptr: manual mode.
  void SetTrajectory(std::shared_ptr<const Trajectory> trajectory) { this->Path = std::move(trajectory); }
  /// A hand holding the stylus (set while stopped): the scripted motion is where it means to be,
  /// with its tremor and drift; the force written pushes it (rpSimulatedHand.h). nullptr: the
  /// stylus follows the script exactly, whatever the force.
  void SetHand(std::unique_ptr<SimulatedHand> hand) { this->Hand = std::move(hand); }
  const SimulatedHand* GetHand() const { return this->Hand.get(); }
  /// Manual mode: the stylus pose, from any one thread (e.g. the viewer's mouse).
  void SetManualPose(const Pose& pose) { this->Manual.Publish(pose); }
  void SetButtons(uint32_t buttons) { this->ButtonState.store(buttons); }
  /// Makes Read() report a device error (to exercise the watchdog).
  void InjectFault(bool fault) { this->Fault.store(fault); }
  /// The last force written (any thread).
  Vec3 LastForce() const;
  uint64_t ForceWrites() const { return this->LastForceValue.PublishCount(); }

 private:
  DeviceInfo Description;
  bool IsOpen = false;
  std::shared_ptr<const Trajectory> Path;
  std::unique_ptr<SimulatedHand> Hand;
  Vec3 HeldForce;  // servo thread: the force written last, in the device frame
  LatestValue<Pose> Manual;
  LatestValue<Vec3> LastForceValue;
  std::atomic<bool> Fault{false};
  std::atomic<uint32_t> ButtonState{0};
  Vec3 PreviousManual;  // servo thread
  double PreviousTime = -1;
};

}  // namespace rp
