#pragma once
// What PlusServer's StartRecording and StopRecording do on our server: a PLUS sequence of every
// tool's newest pose, one frame per send tick, streamed to a new file in the recording folder
// (rpRecordingFolder.h: the client's OutputFilename is checked there, made unique when it
// exists) by PlusSequenceWriter (memory flat however long; a full disk stops the recording and
// leaves a readable file of the frames written). Runs on the server thread; time stamps are the
// caller's (a faked clock in tests).
#include <ctime>
#include <memory>
#include <string>

#include "rpPlusSequenceWriter.h"
#include "rpToolPose.h"

namespace rp {

class RecordingFolder;

class PlusRecorder {
 public:
  /// Starts recording to `requested` (a client's OutputFilename) in `folder`. `message`: the
  /// reply text (the file written to, and why it is not the one asked for) or why it cannot.
  bool Start(const RecordingFolder& folder, const std::string& requested, std::string& message,
             std::time_t now = std::time(nullptr));
  /// Starts on a file already open for writing (`path` names it; tests).
  bool Start(int fd, const std::string& path, std::string& message);
  bool Active() const { return this->Writer != nullptr; }
  /// The file being written ("" when not recording).
  std::string File() const { return this->Writer ? this->Writer->Path() : std::string(); }

  /// One frame at `timestamp`: every slot of `table` that `reader` has a pose of, with its
  /// state. False when the recording has stopped on an error (`Problem()` says which); true once
  /// per such stop in `stoppedNow`, for the log.
  bool Record(double timestamp, const ToolPoseTable& table, const ToolPoseReader& reader, bool* stoppedNow = nullptr);
  /// Why the recording stopped early ("" while it runs).
  std::string Problem() const { return this->Writer ? this->Writer->Error() : std::string(); }

  /// Ends the recording. `message`: "Recording N frames successful to file X" (PLUS's reply), or
  /// why it failed (the frames written before a failure are kept, readable).
  bool Stop(std::string& message);
  const PlusSequenceWriter* CurrentWriter() const { return this->Writer.get(); }

 private:
  std::unique_ptr<PlusSequenceWriter> Writer;
  bool Reported = false;  // the stop on an error was handed to the log
};

}  // namespace rp
