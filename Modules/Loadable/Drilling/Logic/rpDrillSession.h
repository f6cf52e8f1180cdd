#pragma once
// One drilling session, whoever runs it: the viewer's panel (through vtkRPDrillingLogic), the
// `drill` command, the demo, tests and benchmarks. It drives three parts:
//   servo   1 kHz: device → burr → cut → force (rpDrillServo)
//   display 30 Hz: re-contour dirty blocks, post the mesh (rpDrillDisplay)
//   owner   30 Hz: Update() takes the mesh (to swap into a model node), drains the path record
//                  into the recording file and the path, collects retired haptic scenes.
// Two ways to drive them, the same servo, display and Update() in both:
//   - Start() / Update() / Stop(): real time, the servo and display threads on the wall clock,
//     the owner calling Update() from a display-rate timer (the viewer);
//   - Run(): to the end (a Finished() test or MaxSeconds of session time), either real time
//     (Start, Update at display rate, Stop) or scripted: the same ticks on the caller's thread on
//     a simulated clock, as fast as the CPU allows (deterministic: the CLI, the demo, replays).
// Scripted, the display's frame runs between ticks on the same thread; a caller that wants only
// the last mesh (MeshEveryFrame = false) gets it assembled once, at the end, so no frame fills the
// servo's cache with the whole bone's mesh.
// The bone and its display belong to the caller (they outlive a session: drilling can stop and go
// on); the device is any HapticDevice (the simulated one moved by the panel, following a tracked
// tool or scripted; the OpenHaptics device).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpDrillDisplay.h"
#include "rpDrillRecording.h"
#include "rpHapticScene.h"
#include "rpProgress.h"
#include "rpServoLoop.h"

class vtkPolyData;

namespace rp {

/// How Run() drives a session to its end.
struct DrillRunOptions {
  bool Realtime = false;                                   // threads and wall clock, or scripted
  double MaxSeconds = 60;                                  // give up after this (session time)
  double SettleSeconds = 0.05;                             // keep going this long after Finished
  std::function<DrillControl(double time)> Schedule;       // burr switch, radius, speed over time
  std::function<bool(const DrillState&)> Finished;         // e.g. the burr reached the target
  std::function<void(vtkPolyData*)> OnMesh;                // caller's thread: a new bone mesh
  bool MeshEveryFrame = true;                              // scripted: false builds only the last mesh
                                                           // (real time: always every frame)
  ProgressCallback Progress;
};

struct DrillRunResult {
  DrillState Final;
  bool Finished = false;       // Finished() said so (else MaxSeconds ran out)
  uint64_t Ticks = 0;
  TimingStats TickCompute;     // µs per servo tick (scripted: thread CPU time; real time: the loop's)
  ServoStats Servo;            // real-time mode only
  MachineLoad Load;            // what the machine did to the servo thread over the run (scripted: the caller's thread)
  double WallSeconds = 0;
  std::vector<DisplayFrame> Frames;   // display frames that re-contoured blocks
  std::vector<DrillRecordLine> Records;  // every tick's record (Options::KeepRecords)
};

class DrillSession {
 public:
  struct Options {
    DrillServoOptions Servo;
    DrillControl Control;       // the burr at the start (SetControl changes it)
    ServoLoop::Options Loop;    // real time
    double DisplayHz = 30;
    std::string RecordPath;     // drill recording ("" none)
    bool StartCut = false;      // the recording says the burr was placed cutting (Servo().PlaceBurr)
    bool KeepRecords = false;   // every tick's record in Records() (charts, reports)
    bool KeepPath = true;       // the burr's path at 100 Hz in Path() (pictures); with neither, and
                                // no recording, the servo publishes no records
    /// The virtual fixtures of this session (rpToolConstraint.h), made when it is prepared; a
    /// running session takes new ones through Servo().Constraints().Publish().
    std::function<std::unique_ptr<ToolConstraints>()> MakeConstraints;
  };

  /// `bone` and `display` (a DrillDisplay of that bone, initialised) outlive the session.
  DrillSession(HapticDevice& device, DrillVolume& bone, DrillDisplay& display);
  ~DrillSession();
  DrillSession(const DrillSession&) = delete;
  DrillSession& operator=(const DrillSession&) = delete;

  /// Opens the device, makes the servo (the protected structures' surface and the scene's other
  /// haptic models are optional) and opens the recording. Then Start() or Run().
  bool Prepare(const Options& options, const TriangleMesh& protectedSurface, std::unique_ptr<HapticScene> others,
               std::string& error);
  /// Real time: starts the servo and display threads (after Prepare).
  bool Start(std::string& error);
  /// Display-rate update (owner thread): the newest bone mesh, or nullptr when unchanged.
  vtkSmartPointer<vtkPolyData> Update();
  /// Stops the threads, contours and takes what is left, closes the recording and the device.
  /// Returns the last mesh (nullptr when unchanged since the last Update).
  vtkSmartPointer<vtkPolyData> Stop();
  bool Running() const { return this->Loop.Running(); }
  /// Runs the prepared session to its end, scripted or real time, then stops it.
  bool Run(const DrillRunOptions& run, DrillRunResult& result, std::string& error);

  /// The burr switch, radius and speed, any time (owner thread).
  void SetControl(const DrillControl& control);
  DrillServo& Servo() { return *this->Task; }
  const DrillDisplay& Display() const { return this->Frames; }
  const ServoLoop& Scheduler() const { return this->Loop; }
  /// Burr centres of the path recorded so far (decimated to 100 Hz, for pictures).
  const std::vector<Vec3>& Path() const { return this->PathPoints; }
  /// Every tick's record so far (Options::KeepRecords).
  const std::vector<DrillRecordLine>& Records() const { return this->Kept; }
  size_t Recorded() const { return this->Writer.Count(); }

 private:
  bool RunScripted(const DrillRunOptions& run, DrillRunResult& result);
  bool RunRealtime(const DrillRunOptions& run, DrillRunResult& result, std::string& error);

  HapticDevice& Device;
  DrillVolume& Bone;
  DrillDisplay& Frames;
  Options Settings;
  std::unique_ptr<DrillServo> Task;
  ServoLoop Loop;
  BVH ProtectedTree;
  DrillRecordWriter Writer;
  std::vector<Vec3> PathPoints;
  std::vector<DrillRecordLine> Kept;
  double LastPathTime = -1, Rpm = 0;
  bool DeviceOpen = false;
};

}  // namespace rp
