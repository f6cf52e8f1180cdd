#include "rpPlusRecorder.h"

#include <unistd.h>

#include "rpRecordingFolder.h"

namespace rp {

bool PlusRecorder::Start(const RecordingFolder& folder, const std::string& requested, std::string& message, std::time_t now) {
  if (this->Writer) {
    message = "already recording to " + this->Writer->Path();
    return false;
  }
  RecordingFolder::Created created;
  if (!folder.Create(requested, created, message, now)) return false;
  if (!this->Start(created.Fd, created.Path, message)) return false;
  if (created.MadeUnique)  // PLUS users expect a recording, not a refusal: a new name, said in the reply
    message = "Recording to " + created.Path + " started (" + requested + " exists in the recording folder: kept, not overwritten).";
  return true;
}

bool PlusRecorder::Start(int fd, const std::string& path, std::string& message) {
  if (this->Writer) {
    ::close(fd);
    message = "already recording to " + this->Writer->Path();
    return false;
  }
  auto writer = std::make_unique<PlusSequenceWriter>();
  if (!writer->Open(fd, path, message)) return false;
  this->Writer = std::move(writer);
  this->Reported = false;
  message = "Recording to " + path + " started.";
  return true;
}

bool PlusRecorder::Record(double timestamp, const ToolPoseTable& table, const ToolPoseReader& reader, bool* stoppedNow) {
  if (stoppedNow) *stoppedNow = false;
  if (!this->Writer) return false;
  PlusSequenceWriter& w = *this->Writer;
  if (!w.Failed()) {
    w.BeginFrame(timestamp);
    double m[16];
    for (int slot = 0; slot < table.Count(); ++slot) {
      const ToolPoseReader::Sample& s = reader.Last(slot);
      if (!s.Valid) continue;
      s.Pose.ToMatrix(m);
      w.AddTransform(table.Name(slot), m, s.Pose.State);
    }
    if (w.EndFrame()) return true;
  }
  if (stoppedNow && !this->Reported) *stoppedNow = true;
  this->Reported = true;
  return false;
}

bool PlusRecorder::Stop(std::string& message) {
  if (!this->Writer) {
    message = "not recording";
    return false;
  }
  std::unique_ptr<PlusSequenceWriter> writer = std::move(this->Writer);
  std::string error;
  if (!writer->Close(&error)) {
    message = "Recording stopped early: " + error;
    return false;
  }
  message = "Recording " + std::to_string(writer->FramesWritten()) + " frames successful to file " + writer->Path();
  return true;
}

}  // namespace rp
