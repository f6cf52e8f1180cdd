#pragma once
// The drill path of a session, as text a trainer can keep and replay (like the tracking
// recordings): a header with the burr and the bone's voxel size, then one line per servo tick:
//   # RoboPlan drill recording 1
//   # voxel 0.3 feed 2 reference-rpm 60000 start-cut 1
//   # time hipR hipA hipS proxyR proxyA proxyS forceR forceA forceS radius rpm removedMm3 protectedMm flags
// Replaying the HIP path with the same burr switch, radius and speed on the same bone gives the
// same removal (rpDrillRun ticks the servo at the recorded times).
#include <cstdio>
#include <string>
#include <vector>

#include "rpDrillServo.h"

namespace rp {

struct DrillRecordingInfo {
  double Voxel = 0, FeedRate = 0, ReferenceRpm = 0;
  bool StartCut = false;  // the burr was placed cutting at the first position (roboplan drill --from)
};

struct DrillRecordLine {
  DrillRecord Record;
  double Rpm = 0;
};

struct DrillRecording {
  DrillRecordingInfo Info;
  std::vector<DrillRecordLine> Lines;
  /// False names the file and line.
  static bool Read(const std::string& path, DrillRecording& recording, std::string& error);
};

/// Appends records as they are drained from the servo (main thread); Close() flushes.
class DrillRecordWriter {
 public:
  ~DrillRecordWriter();
  bool Open(const std::string& path, const DrillRecordingInfo& info, std::string& error);
  void Add(const DrillRecord& record, double rpm);
  void Close();
  bool IsOpen() const { return this->File != nullptr; }
  size_t Count() const { return this->Written; }

 private:
  std::FILE* File = nullptr;
  size_t Written = 0;
};

}  // namespace rp
