#pragma once
// Recording of a tracking session (every pose of every tool, with its time and status) to a
// text file, and its replay into a ToolPoseTable at the recorded pace (for tests, demos and
// post-processing such as `roboplan pivot`).
//
// File: "# RoboPlan tracking recording 1" then one line per pose:
//   <time s> <tool> <state> <qw> <qx> <qy> <qz> <tx> <ty> <tz> <error> <frame>
#include <atomic>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "rpToolPose.h"

namespace rp {

struct Recording {
  struct Sample {
    double Time = 0;
    int Tool = 0;  // index into Tools
    ToolPose Pose;
  };
  std::vector<std::string> Tools;
  std::vector<Sample> Samples;

  int ToolIndex(const std::string& name) const;  // -1 when absent
  std::vector<ToolPose> PosesOf(const std::string& name) const;
  /// Throws std::runtime_error naming the file and line.
  static Recording Read(const std::string& path);
  /// Writes atomically; throws std::runtime_error.
  void Write(const std::string& path) const;
};

/// Appends poses as they come (main thread), flushing on Close.
class RecordingWriter {
 public:
  ~RecordingWriter();
  bool Open(const std::string& path, std::string& error);
  void Add(const char* tool, double time, const ToolPose& pose);
  void Close();
  size_t Count() const { return this->Written; }

 private:
  std::FILE* File = nullptr;
  size_t Written = 0;
};

/// Replays a recording into a pose table from its own thread (the "tracker" of a replay).
class RecordingPlayer {
 public:
  RecordingPlayer(const Recording& recording, double speed = 1.0, bool loop = false);
  ~RecordingPlayer();
  void Start();
  void Stop();
  bool Finished() const { return this->Done.load(); }
  const ToolPoseTable& Poses() const { return this->Table; }

 private:
  const Recording& Source;
  double Speed;
  bool Loop;
  ToolPoseTable Table;
  std::vector<int> Slots;
  std::thread Thread;
  std::atomic<bool> StopRequested{false}, Done{false};
};

}  // namespace rp
