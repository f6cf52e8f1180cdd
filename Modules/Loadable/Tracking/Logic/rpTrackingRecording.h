#pragma once
// Recording of a tracking session (every pose of every tool, with its time and status) to a
// text file, and its replay into a ToolPoseTable at the recorded pace (for tests, demos and
// post-processing such as `roboplan pivot`). PLUS tracked-frame sequences (.igs.mha, .igs.nrrd;
// rpPlusSequenceFile.h) are read and written by the same Read/Write, chosen by the extension.
//
// File: "# RoboPlan tracking recording 1" then one line per pose:
//   <time s> <tool> <state> <qw> <qx> <qy> <qz> <tx> <ty> <tz> <error> <frame>
#include <atomic>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "rpPlusSequenceWriter.h"
#include "rpPoseSource.h"
#include "rpToolPose.h"
#include "rpWorkerThread.h"

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

/// Appends poses as they come (main thread), flushing on Close. The extension chooses the format
/// as Recording::Write does: RoboPlan's text lines, or a PLUS sequence (.igs.mha/.igs.nrrd)
/// streamed by PlusSequenceWriter (one frame per time stamp, the header's count written as it
/// goes). Either way memory stays flat however long it runs.
class RecordingWriter {
 public:
  ~RecordingWriter();
  bool Open(const std::string& path, std::string& error);
  void Add(const char* tool, double time, const ToolPose& pose);
  /// False with `error` when the file could not be written completely.
  bool Close(std::string* error = nullptr);
  size_t Count() const { return this->Written; }

 private:
  std::FILE* File = nullptr;
  std::unique_ptr<PlusSequenceWriter> Plus;  // a PLUS sequence
  double FrameTime = 0;
  bool FrameOpen = false;
  std::string Name;  // scratch: <Tool>ToTracker
  size_t Written = 0;
};

/// Replays a recording into a pose table from its own thread at the recorded pace (pose source
/// "replay": the "tracker" of a replay). Tool names become transform names (Stylus →
/// StylusToTracker; names that already end in ToTracker are kept).
class RecordingPlayer : public PoseSource {
 public:
  explicit RecordingPlayer(Recording recording, double speed = 1.0, bool loop = false);
  ~RecordingPlayer() override;
  /// Address = the recording file; options "speed" (> 0) and "loop" (1). Throws
  /// std::invalid_argument for a bad option, std::runtime_error for an unreadable recording.
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config);

  bool Start(std::string& error) override;
  using PoseSource::Start;
  void Stop() override;
  const ToolPoseTable& Poses() const override { return this->Table; }
  bool Connected() const override { return !this->Done.load(); }
  std::string StatusText() const override { return this->Finished() ? "replay finished" : "replaying"; }
  nlohmann::json StatisticsJson() const override;
  bool Finished() const override { return this->Done.load(); }

 private:
  void Run();
  Recording Source;
  double Speed;
  bool Loop;
  ToolPoseTable Table;
  std::vector<int> Slots;
  WorkerThread Worker;
  std::atomic<bool> Done{false};
  std::atomic<uint64_t> Played{0};
};

}  // namespace rp
