#pragma once
// Runs haptics for a scene (main thread owner): the device, the 1 kHz servo loop, the session
// log writer, and the scene bridge. Update() is the display-rate call: it rebuilds the haptic
// scene when haptic models changed (meshes read here, BVH built on a worker thread, swapped into
// the servo loop atomically), frees retired scenes, and copies the servo state into tool nodes.
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "rpHapticSceneBridge.h"
#include "rpSessionLog.h"

namespace rp {

class HapticSession {
 public:
  struct Options {
    MaterialTable Materials = MaterialTable::Defaults();
    RendererOptions Renderer;
    std::vector<Vec3> ToolPoints{Vec3{}};  // stylus frame; [0] is the tip
    double RampSeconds = 0.5;
    ServoLoop::Options Loop;
    std::string LogPath;  // empty: no session log file
  };

  explicit HapticSession(HapticDevice& device);
  ~HapticSession();

  /// Builds the first haptic scene (synchronously), opens the device and starts the servo loop.
  bool Start(vtkRPScene* scene, const Options& options, std::string& error);
  /// Display-rate update (main thread). Returns true when the tool nodes were updated.
  bool Update();
  void Stop();
  bool Running() const { return this->Loop.Running(); }

  HapticServo& Servo() { return *this->Task; }
  const ServoLoop& Scheduler() const { return this->Loop; }
  SessionLogWriter& Log() { return this->Writer; }
  const std::vector<std::string>& Warnings() const { return this->WarningList; }
  const std::vector<std::string>& TissueNames() const { return this->Names; }
  size_t SceneTriangles() const { return this->Triangles; }
  uint64_t ScenesBuilt() const { return this->Builds.load(); }

 private:
  void StartRebuild();
  HapticDevice& Device;
  std::unique_ptr<HapticServo> Task;
  ServoLoop Loop;
  SessionLogWriter Writer;
  vtkRPScene* Scene = nullptr;
  Options Settings;
  std::vector<std::string> WarningList, Names;
  unsigned long Signature = 0;
  size_t Triangles = 0;
  std::thread Builder;
  std::atomic<bool> BuildDone{false};
  std::unique_ptr<HapticScene> Built;
  std::atomic<uint64_t> Builds{0};
};

}  // namespace rp
