#pragma once
// Runs a drilling session to its end with the three threads of the viewer, or scripted on one
// thread (the same ticks on a simulated clock, as fast as the CPU allows: deterministic, for
// tests, the CLI, the demo and replays):
//   servo   1 kHz: device → burr → cut → force (rpDrillServo)
//   display 30 Hz: re-contour dirty blocks, post the mesh (rpDrillDisplay)
//   caller  30 Hz: take the mesh (OnMesh: swap it into a model node), drain the path record
//                  into the recording file, watch the state (Finished) and report progress.
// Scripted, the display's frame runs between ticks on the same thread; a caller that wants only
// the last mesh (MeshEveryFrame = false) gets it assembled once, at the end, so no frame fills
// the servo's cache with the whole bone's mesh.
#include <functional>
#include <string>
#include <vector>

#include "rpDrillDisplay.h"
#include "rpDrillRecording.h"
#include "rpProgress.h"
#include "rpServoLoop.h"

class vtkPolyData;

namespace rp {

struct DrillRunOptions {
  bool Realtime = false;                                   // threads and wall clock, or scripted
  double DisplayHz = 30;
  double MaxSeconds = 60;                                  // give up after this (session time)
  double SettleSeconds = 0.05;                             // keep going this long after Finished
  std::function<DrillControl(double time)> Schedule;       // burr switch, radius, speed over time
  std::function<bool(const DrillState&)> Finished;         // e.g. the burr reached the target
  std::string RecordPath;                                  // drill recording ("" none)
  DrillRecordingInfo RecordInfo;
  bool KeepRecords = true;                                 // keep the path in the result (charts)
  std::function<void(vtkPolyData*)> OnMesh;                // caller's thread: a new bone mesh
  bool MeshEveryFrame = true;                              // scripted: false builds only the last mesh
                                                           // (real time: always every frame)
  ServoLoop::Options Loop;                                 // real-time mode
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
  std::vector<DrillRecordLine> Records;
};

bool RunDrill(DrillServo& servo, DrillDisplay& display, const DrillRunOptions& options, DrillRunResult& result,
              std::string& error);

/// Nearest-rank percentile (q in 0–1) of a run's timings, e.g. the frames' re-contour ms; 0 when empty.
double NearestRankPercentile(std::vector<double> values, double q);

}  // namespace rp
