#include "rpExecutionPath.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/Core>

#include "rpDrillRecording.h"
#include "rpPlusConfiguration.h"
#include "rpPlusSequenceFile.h"
#include "rpPlusTracking.h"
#include "rpTransformRepository.h"
#include "rpStrings.h"

namespace rp {

namespace {

bool StartsWithMagic(const std::string& file, const std::string& magic) {
  std::ifstream in(file);
  std::string line;
  return in && std::getline(in, line) && line.rfind(magic, 0) == 0;
}

bool ReadDrillRecordingPath(const std::string& file, ExecutionPath& path, std::string& error) {
  DrillRecording recording;
  if (!DrillRecording::Read(file, recording, error)) return false;
  path.Kind = "drill-recording";
  path.Samples = recording.Lines.size();
  for (const DrillRecordLine& l : recording.Lines) {
    if (!(l.Record.Flags & DrillRecordFlags::BurrOn)) {
      ++path.Skipped;
      continue;
    }
    path.Points.push_back(l.Record.Proxy);
    path.ToolRadiusMm = std::max(path.ToolRadiusMm, static_cast<double>(l.Record.Radius));
  }
  if (path.Points.empty()) {
    error = "'" + file + "': the burr never ran in this recording (no tick with the burr on)";
    return false;
  }
  return true;
}

// A PLUS sequence's transform repository: the configuration's CoordinateDefinitions are its fixed
// links, every transform the recording holds a live one (as PLUS's repository takes a frame);
// `live` gives each sequence transform's edge (-1: left out, it would close a loop).
bool BuildSequenceRepository(const std::string& file, const std::string& configurationFile, PlusSequence& sequence,
                             TransformRepository& repository, std::vector<int>& live, std::string& error) {
  try {
    sequence = ReadPlusSequence(file);
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  if (!configurationFile.empty()) {
    plus::Configuration configuration;
    if (!plus::ReadConfiguration(configurationFile, {}, configuration, error)) return false;
    std::vector<int> edges;
    std::vector<plus::Refusal> refused;
    BuildRepository(configuration, nullptr, repository, edges, refused);
    for (const plus::Refusal& r : refused) {
      error = configurationFile + ": " + r.What + ": " + r.Why;
      return false;
    }
  }
  live.assign(sequence.TransformNames.size(), -1);
  for (size_t i = 0; i < sequence.TransformNames.size(); ++i) {
    std::string a, b, why;
    if (!SplitTransformName(sequence.TransformNames[i], a, b, why)) continue;
    live[i] = repository.DeclareLive(a, b, why);
  }
  return true;
}

bool ReadPlusPath(const std::string& file, const ExecutionPathOptions& options, ExecutionPath& path, std::string& error) {
  if (options.Transform.empty()) {
    error = "'" + file + "' is a PLUS sequence: name the transform to follow (e.g. StylusTipToReference)";
    return false;
  }
  std::string from, to;
  if (!SplitTransformName(options.Transform, from, to, error)) {
    error = "the transform '" + options.Transform + "': " + error;
    return false;
  }
  PlusSequence sequence;
  TransformRepository repository;
  std::vector<int> live;
  if (!BuildSequenceRepository(file, options.Configuration, sequence, repository, live, error)) return false;
  const int route = repository.Prepare(from, to);
  path.Chain = repository.Describe(route);
  if (path.Chain.empty()) {
    std::string names;
    for (const std::string& n : sequence.TransformNames) names += (names.empty() ? "" : ", ") + n;
    error = "'" + file + "': " + options.Transform + " cannot be computed from its transforms (" + names + ")" +
            (options.Configuration.empty() ? " without a PLUS configuration giving the fixed ones (e.g. StylusTipToStylus)"
                                           : " and the configuration's CoordinateDefinitions");
    return false;
  }
  path.Kind = "plus-sequence";
  path.Samples = sequence.Frames.size();
  for (const PlusSequence::Frame& frame : sequence.Frames) {
    for (size_t i = 0; i < live.size(); ++i) {
      if (live[i] < 0 || i >= frame.Transforms.size()) continue;
      const PlusSequence::Transform& t = frame.Transforms[i];
      const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(t.Matrix);
      repository.SetLive(live[i], m, t.Present && t.State == ToolState::OK ? TransformStatus::OK : TransformStatus::Missing);
    }
    Eigen::Matrix4d m;
    TransformStatus status;
    if (!repository.Evaluate(route, m, status)) {
      ++path.Skipped;
      continue;
    }
    path.Points.push_back({m(0, 3), m(1, 3), m(2, 3)});
  }
  if (path.Points.empty()) {
    error = "'" + file + "': " + options.Transform + " is valid in none of its " + std::to_string(path.Samples) + " frames";
    return false;
  }
  return true;
}

bool ReadCsvPath(const std::string& file, ExecutionPath& path, std::string& error) {
  std::ifstream in(file);
  if (!in) {
    error = "cannot open '" + file + "'";
    return false;
  }
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    std::string text = Trim(line);
    if (text.empty() || text[0] == '#') continue;
    if (!header) {
      std::string upper = text;
      upper.erase(std::remove_if(upper.begin(), upper.end(), [](unsigned char c) { return std::isspace(c); }), upper.end());
      std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
      if (upper != "R,A,S") {
        error = file + ":" + std::to_string(number) + ": expected the header 'R,A,S' (tool-tip points in RAS, mm), found '" +
                text + "'";
        return false;
      }
      header = true;
      continue;
    }
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream fields(text);
    Vec3 p;
    std::string rest;
    if (!(fields >> p.x >> p.y >> p.z) || (fields >> rest) || !std::isfinite(p.x) || !std::isfinite(p.y) ||
        !std::isfinite(p.z)) {
      error = file + ":" + std::to_string(number) + ": expected three numbers R,A,S, found '" + Trim(line) + "'";
      return false;
    }
    path.Points.push_back(p);
  }
  if (!header) {
    error = "'" + file + "' is empty (expected the header 'R,A,S' and one point per row)";
    return false;
  }
  path.Kind = "csv";
  path.Samples = path.Points.size();
  return true;
}

}  // namespace

bool ReadExecutionPath(const std::string& file, const ExecutionPathOptions& options, ExecutionPath& path,
                       std::string& error) {
  path = ExecutionPath{};
  std::ifstream probe(file);
  if (!probe) {
    error = "cannot open the path '" + file + "'";
    return false;
  }
  if (StartsWithMagic(file, "# RoboPlan drill recording")) return ReadDrillRecordingPath(file, path, error);
  if (IsPlusSequenceFileName(file)) return ReadPlusPath(file, options, path, error);
  std::string lower = file;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower.size() >= 4 && lower.compare(lower.size() - 4, 4, ".csv") == 0) return ReadCsvPath(file, path, error);
  error = "'" + file + "' is not a path RoboPlan scores: a drilling recording ('# RoboPlan drill recording'), a PLUS "
          "sequence (.igs.mha, .mha, .mhd, .nrrd) or a CSV with the header R,A,S";
  return false;
}

bool ListPathTransforms(const std::string& file, const std::string& configuration, std::vector<std::string>& names,
                        std::string& error) {
  names.clear();
  if (!IsPlusSequenceFileName(file)) return true;  // a recording or a CSV: no transform to choose
  PlusSequence sequence;
  TransformRepository repository;
  std::vector<int> live;
  if (!BuildSequenceRepository(file, configuration, sequence, repository, live, error)) return false;
  std::vector<std::string> tips, others;
  const std::vector<std::string>& frames = repository.Frames();
  for (const std::string& from : frames)
    for (const std::string& to : frames) {
      if (from == to || repository.Describe(repository.Prepare(from, to)).empty()) continue;
      (from.find("Tip") != std::string::npos ? tips : others).push_back(from + "To" + to);
    }
  names = tips;
  names.insert(names.end(), others.begin(), others.end());
  return true;
}

}  // namespace rp
