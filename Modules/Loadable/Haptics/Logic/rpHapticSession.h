#pragma once
// Runs haptics for a scene (main thread owner): the device, the 1 kHz servo loop, the session
// log writer, and the scene bridge. Update() is the display-rate call: it rebuilds the haptic
// scene when haptic models changed (meshes read here, BVH built on a worker thread, swapped into
// the servo loop atomically), frees retired scenes, and copies the servo state into tool nodes.
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "rpHapticSceneBridge.h"
#include "rpSessionLog.h"

namespace rp {

/// Every tick's log record folded into the figures a run reports (the `haptics` command, the
/// demo's passes): gathered on the log writer thread, read after Stop.
struct HapticForceSummary {
  uint64_t Records = 0, ContactTicks = 0, ClampedTicks = 0, WatchdogTicks = 0, StallLimitedTicks = 0;
  double MaxForce = 0, SumForceInContact = 0;  // N
  std::map<int, uint64_t> TissueTicks;         // material index → ticks in contact
  /// Per material: penetration |HIP − proxy| (mm) and force (N) of every 5th tick in contact.
  std::map<int, std::pair<std::vector<double>, std::vector<double>>> ForceCurves;
  void Add(const HapticLogRecord& record);
  double MeanForceInContact() const { return this->ContactTicks ? this->SumForceInContact / this->ContactTicks : 0.0; }
  double ContactFraction() const { return this->Records ? double(this->ContactTicks) / double(this->Records) : 0.0; }
};

class HapticSession {
 public:
  struct Options {
    MaterialTable Materials;  // empty: LoadMaterialTable() (Resources/Materials/materials.json)
    RendererOptions Renderer;
    std::vector<Vec3> ToolPoints{Vec3{}};  // stylus frame; [0] is the tip
    double RampSeconds = 0.5;
    bool PosesInScene = false;  // the device's poses are in RAS already (rpToolInput.h): a simulated
                                // device moved by the viewer, a script in RAS or a tracked tool
    ServoLoop::Options Loop;
    std::string LogPath;  // empty: no session log file
    bool Summarize = false;  // gather Summary() from every tick's record
    /// The virtual fixtures of this session (rpToolConstraint.h), made when it starts; a running
    /// session takes new ones through Servo().Constraints().Publish().
    std::function<std::unique_ptr<ToolConstraints>()> MakeConstraints;
  };

  explicit HapticSession(HapticDevice& device);
  ~HapticSession();

  /// Builds the first haptic scene (synchronously), opens the device and starts the servo loop.
  /// Tissues the device cannot render stably are clamped, each with a warning (Warnings(),
  /// Clamps()).
  bool Start(vtkRPScene* scene, const Options& options, std::string& error);
  /// Display-rate update (main thread). Returns true when the tool nodes were updated. When the
  /// measured servo period (p99) grows past the nominal one, the passivity limits follow it and
  /// tissues newly clamped get a warning.
  bool Update();
  void Stop();
  bool Running() const { return this->Loop.Running(); }

  HapticServo& Servo() { return *this->Task; }
  const ServoLoop& Scheduler() const { return this->Loop; }
  SessionLogWriter& Log() { return this->Writer; }
  const std::vector<std::string>& Warnings() const { return this->WarningList; }
  const std::vector<std::string>& TissueNames() const { return this->Names; }
  /// The material table in use and, per tissue, what was asked and what the device renders.
  const MaterialTable& Materials() const { return this->Settings.Materials; }
  const std::vector<MaterialClamp>& Clamps() const { return this->ClampList; }
  /// The device's limits (name, peak force, nominal maximum stiffness...).
  const DeviceInfo& DeviceLimits() const { return this->Device.Info(); }
  /// The servo period the clamps assume (s): nominal, or the measured p99 when longer.
  double StabilityPeriod() const { return this->Period; }
  size_t SceneTriangles() const { return this->Triangles; }
  /// The run's figures (Options::Summarize), complete after Stop().
  const HapticForceSummary& Summary() const { return this->Figures; }
  uint64_t ScenesBuilt() const { return this->Builds.load(); }

 private:
  void StartRebuild();
  void UpdateClamps(double period);
  HapticDevice& Device;
  std::unique_ptr<HapticServo> Task;
  ServoLoop Loop;
  SessionLogWriter Writer;
  vtkRPScene* Scene = nullptr;
  Options Settings;
  std::vector<std::string> WarningList, Names;
  std::vector<MaterialClamp> ClampList;
  double Period = 0.001;
  unsigned long Signature = 0;
  size_t Triangles = 0;
  std::thread Builder;
  std::atomic<bool> BuildDone{false};
  std::unique_ptr<HapticScene> Built;
  std::atomic<uint64_t> Builds{0};
  HapticForceSummary Figures;  // written by the log writer thread while running
};

}  // namespace rp
