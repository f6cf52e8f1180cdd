#include "rpDrillRecording.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rp {

namespace {
const char* kMagic = "# RoboPlan drill recording 1";
}

DrillRecordWriter::~DrillRecordWriter() { this->Close(); }

bool DrillRecordWriter::Open(const std::string& path, const DrillRecordingInfo& info, std::string& error) {
  this->Close();
  this->File = std::fopen(path.c_str(), "w");
  if (!this->File) {
    error = "drill recording: cannot write '" + path + "': " + std::strerror(errno);
    return false;
  }
  std::fprintf(this->File, "%s\n# voxel %.6g feed %.6g reference-rpm %.6g start-cut %d\n", kMagic, info.Voxel,
               info.FeedRate, info.ReferenceRpm, info.StartCut ? 1 : 0);
  std::fprintf(this->File,
               "# time hipR hipA hipS proxyR proxyA proxyS forceR forceA forceS radius rpm removedMm3 protectedMm flags\n");
  this->Written = 0;
  return true;
}

void DrillRecordWriter::Add(const DrillRecord& r, double rpm) {
  if (!this->File) return;
  std::fprintf(this->File, "%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.5f %.5f %.5f %.4f %.0f %.4f %.4f %u\n", r.Time, r.Hip.x,
               r.Hip.y, r.Hip.z, r.Proxy.x, r.Proxy.y, r.Proxy.z, r.Force.x, r.Force.y, r.Force.z, r.Radius, rpm,
               r.RemovedTotalMm3, std::isfinite(r.ProtectedDistance) ? r.ProtectedDistance : -1.0f, r.Flags);
  ++this->Written;
}

void DrillRecordWriter::Close() {
  if (this->File) std::fclose(this->File);
  this->File = nullptr;
}

bool DrillRecording::Read(const std::string& path, DrillRecording& recording, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "drill recording: cannot open '" + path + "'";
    return false;
  }
  std::string line;
  if (!std::getline(in, line) || line.rfind(kMagic, 0) != 0) {
    error = "'" + path + "' is not a RoboPlan drill recording (missing '" + kMagic + "')";
    return false;
  }
  DrillRecording out;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream fields(line.substr(1));
      std::string key;
      while (fields >> key) {
        double value;
        if (key == "voxel" && fields >> value) out.Info.Voxel = value;
        if (key == "feed" && fields >> value) out.Info.FeedRate = value;
        if (key == "reference-rpm" && fields >> value) out.Info.ReferenceRpm = value;
        if (key == "start-cut" && fields >> value) out.Info.StartCut = value != 0;
      }
      continue;
    }
    std::istringstream fields(line);
    DrillRecordLine l;
    DrillRecord& r = l.Record;
    float radius, removed, protectedMm;
    if (!(fields >> r.Time >> r.Hip.x >> r.Hip.y >> r.Hip.z >> r.Proxy.x >> r.Proxy.y >> r.Proxy.z >> r.Force.x >>
          r.Force.y >> r.Force.z >> radius >> l.Rpm >> removed >> protectedMm >> r.Flags)) {
      error = path + ":" + std::to_string(number) + ": expected 15 fields (" +
              "time hip×3 proxy×3 force×3 radius rpm removedMm3 protectedMm flags)";
      return false;
    }
    if (!out.Lines.empty() && !(r.Time > out.Lines.back().Record.Time)) {
      error = path + ":" + std::to_string(number) + ": time does not increase";
      return false;
    }
    r.Radius = radius;
    r.RemovedTotalMm3 = removed;
    r.ProtectedDistance = protectedMm;
    out.Lines.push_back(l);
  }
  if (out.Lines.size() < 2) {
    error = "'" + path + "' holds fewer than two samples";
    return false;
  }
  recording = std::move(out);
  return true;
}

}  // namespace rp
