#include "rpTrackingRecording.h"

#include "rpTransformNames.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "rpAtomicFile.h"
#include "rpPlusSequenceFile.h"

namespace rp {

namespace {
const char* kMagic = "# RoboPlan tracking recording 1";

ToolState ParseState(const std::string& s) {
  if (s == "OK") return ToolState::OK;
  if (s == "OUT_OF_VOLUME") return ToolState::OutOfVolume;
  if (s == "DISABLED") return ToolState::Disabled;
  return ToolState::Missing;
}

void FormatLine(char* out, size_t size, const char* tool, double time, const ToolPose& p) {
  std::snprintf(out, size, "%.6f %s %s %.9f %.9f %.9f %.9f %.6f %.6f %.6f %.6f %u\n", time, tool, ToolStateName(p.State),
                p.Quaternion[0], p.Quaternion[1], p.Quaternion[2], p.Quaternion[3], p.Translation[0], p.Translation[1],
                p.Translation[2], p.Error, p.Frame);
}
}  // namespace

int Recording::ToolIndex(const std::string& name) const {
  for (size_t i = 0; i < this->Tools.size(); ++i)
    if (this->Tools[i] == name) return static_cast<int>(i);
  return -1;
}

std::vector<ToolPose> Recording::PosesOf(const std::string& name) const {
  std::vector<ToolPose> out;
  const int index = this->ToolIndex(name);
  for (const Sample& s : this->Samples)
    if (s.Tool == index) out.push_back(s.Pose);
  return out;
}

Recording Recording::Read(const std::string& path) {
  if (IsPlusSequenceFileName(path)) return ReadPlusSequence(path).ToRecording();  // a PLUS recording
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open recording " + path);
  std::string line;
  if (!std::getline(in, line) || line.rfind(kMagic, 0) != 0)
    throw std::runtime_error(path + " is not a RoboPlan tracking recording (missing '" + kMagic + "' header)");
  Recording r;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Sample s;
    std::string tool, state;
    ToolPose& p = s.Pose;
    if (!(fields >> s.Time >> tool >> state >> p.Quaternion[0] >> p.Quaternion[1] >> p.Quaternion[2] >> p.Quaternion[3] >>
          p.Translation[0] >> p.Translation[1] >> p.Translation[2] >> p.Error >> p.Frame))
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected 12 fields (time tool state qw qx qy qz tx ty tz error frame)");
    p.State = ParseState(state);
    p.Timestamp = s.Time;
    s.Tool = r.ToolIndex(tool);
    if (s.Tool < 0) {
      r.Tools.push_back(tool);
      s.Tool = static_cast<int>(r.Tools.size()) - 1;
    }
    r.Samples.push_back(s);
  }
  return r;
}

void Recording::Write(const std::string& path) const {
  if (IsPlusSequenceFileName(path)) return WritePlusSequence(PlusSequence::FromRecording(*this), path);
  std::string text = std::string(kMagic) + "\n";
  char line[512];
  for (const Sample& s : this->Samples) {
    FormatLine(line, sizeof line, this->Tools.at(static_cast<size_t>(s.Tool)).c_str(), s.Time, s.Pose);
    text += line;
  }
  std::string error;
  if (!WriteFileAtomically(path, text, error)) throw std::runtime_error("cannot write recording " + path + ": " + error);
}

RecordingWriter::~RecordingWriter() { this->Close(); }

bool RecordingWriter::Open(const std::string& path, std::string& error) {
  this->Close();
  this->Written = 0;
  if (IsPlusSequenceFileName(path)) {
    this->Plus = std::make_unique<PlusSequenceWriter>();
    this->FrameOpen = false;
    return this->Plus->Create(path, error);
  }
  this->File = std::fopen(path.c_str(), "w");
  if (!this->File) {
    error = "cannot write recording " + path + ": " + std::strerror(errno);
    return false;
  }
  std::fprintf(this->File, "%s\n", kMagic);
  return true;
}

void RecordingWriter::Add(const char* tool, double time, const ToolPose& pose) {
  if (this->Plus) {  // one frame per time stamp (the tools a tracker reports together share it)
    if (this->FrameOpen && time != this->FrameTime) this->Plus->EndFrame();
    if (!this->FrameOpen || time != this->FrameTime) this->Plus->BeginFrame(time);
    this->FrameOpen = true;
    this->FrameTime = time;
    this->Name = ToolToTrackerName(tool);
    double m[16];
    pose.ToMatrix(m);
    this->Plus->AddTransform(this->Name.c_str(), m, pose.State);
    ++this->Written;
    return;
  }
  if (!this->File) return;
  char line[512];
  FormatLine(line, sizeof line, tool, time, pose);
  std::fputs(line, this->File);
  ++this->Written;
}

bool RecordingWriter::Close(std::string* error) {
  if (this->File) std::fclose(this->File);
  this->File = nullptr;
  if (!this->Plus) return true;
  if (this->FrameOpen) this->Plus->EndFrame();
  this->FrameOpen = false;
  const bool ok = this->Plus->Close(error);
  this->Plus.reset();
  return ok;
}

RecordingPlayer::RecordingPlayer(Recording recording, double speed, bool loop)
    : Source(std::move(recording)), Speed(speed > 0 ? speed : 1.0), Loop(loop) {
  for (const std::string& name : this->Source.Tools)
    this->Slots.push_back(this->Table.FindOrAdd(ToolToTrackerName(name).c_str()));
}

RecordingPlayer::~RecordingPlayer() { this->Stop(); }

std::unique_ptr<PoseSource> RecordingPlayer::Create(const PoseSourceConfig& config) {
  const double speed = config.Number("speed", 1.0);
  if (!(speed > 0)) throw std::invalid_argument("speed must be > 0");
  const std::string loop = config.Option("loop", "0");
  return std::make_unique<RecordingPlayer>(Recording::Read(config.Address), speed, loop == "1" || loop == "true");
}

bool RecordingPlayer::Start(std::string&) {
  this->Done = false;
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void RecordingPlayer::Stop() { this->Worker.Stop(); }

nlohmann::json RecordingPlayer::StatisticsJson() const {
  return {{"samples", this->Source.Samples.size()}, {"played", this->Played.load()}, {"finished", this->Finished()},
          {"speed", this->Speed}};
}

void RecordingPlayer::Run() {
  do {
    if (this->Source.Samples.empty()) break;
    const double t0 = this->Source.Samples.front().Time;
    const double start = SteadySeconds();
    for (const auto& s : this->Source.Samples) {
      const double due = start + (s.Time - t0) / this->Speed;
      if (!this->Worker.Sleep(due - SteadySeconds())) break;
      ToolPose p = s.Pose;
      p.ReceiveTime = SteadySeconds();
      const int slot = this->Slots[static_cast<size_t>(s.Tool)];
      if (slot >= 0) this->Table.Publish(slot, p);
      ++this->Played;
      this->Ready.Notify();
    }
  } while (this->Loop && !this->Worker.StopRequested());
  this->Done = true;
  this->Ready.Notify();
}

}  // namespace rp
