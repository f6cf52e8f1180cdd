#include "rpSceneFormats.h"

#include <ostream>
#include <set>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpNodeStorage.h"
#include "rpSceneIO.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace rp {
namespace {

// Our scene file's problems ("<file> (<node>): reason") as skipped items.
void AddProblems(const std::vector<std::string>& problems, SceneTransferReport& report) {
  for (const std::string& problem : problems) {
    const size_t split = problem.find("): ");
    if (split == std::string::npos) report.Skipped.push_back({problem, "could not be loaded"});
    else report.Skipped.push_back({problem.substr(0, split + 1), problem.substr(split + 3)});
  }
}

nlohmann::json ReportJson(const std::string& path, const SceneTransferReport& report) {
  nlohmann::json doc;
  const size_t dot = path.find_last_of('.');
  doc["format"] = dot == std::string::npos ? "" : path.substr(dot + 1);
  doc["nodes"] = report.NodesByType;
  doc["files"] = report.Files;
  doc["skipped"] = nlohmann::json::array();
  for (const auto& skip : report.Skipped) doc["skipped"].push_back({{"what", skip.What}, {"why", skip.Why}});
  doc["warnings"] = report.Warnings;
  return doc;
}

std::string CountsText(const std::map<std::string, int>& counts) {
  std::string text;
  for (const auto& [tag, count] : counts) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + tag;
  return text.empty() ? "no nodes" : text;
}

}  // namespace

const std::vector<std::string>& SceneFileExtensions() {
  static const std::vector<std::string> extensions = {SceneFileExtension, ".mrml", ".mrb"};
  return extensions;
}

bool IsSceneFileName(const std::string& path) {
  for (const std::string& extension : SceneFileExtensions())
    if (HasExtension(path, extension)) return true;
  return false;
}

bool ReadSceneFile(const std::string& path, vtkRPScene* scene, SceneTransferReport& report) {
  if (HasExtension(path, ".mrml")) return ReadMrmlScene(path, scene, report);
  if (HasExtension(path, ".mrb")) return ReadMrmlBundle(path, scene, report);
  report = SceneTransferReport();
  const std::vector<vtkRPNode*> before = scene->GetNodes();
  const std::set<vtkRPNode*> old(before.begin(), before.end());
  const SceneLoadReport loaded = LoadScene(scene, path);
  report.Ok = loaded.Ok;
  report.Error = loaded.Error;
  AddProblems(loaded.Problems, report);
  for (vtkRPNode* node : scene->GetNodes())
    if (!old.count(node)) ++report.NodesByType[node->GetNodeTagName()];
  return report.Ok;
}

bool WriteSceneFile(vtkRPScene* scene, const std::string& path, SceneTransferReport& report) {
  if (HasExtension(path, ".mrml")) return WriteMrmlScene(scene, path, report);
  if (HasExtension(path, ".mrb")) return WriteMrmlBundle(scene, path, report);
  report = SceneTransferReport();
  report.Ok = SaveScene(scene, path, report.Error);
  for (vtkRPNode* node : scene->GetNodes()) ++report.NodesByType[node->GetNodeTagName()];
  return report.Ok;
}

int ConvertSceneFile(const std::string& input, const std::string& output, bool json, std::ostream& out,
                     std::ostream& err) {
  vtkNew<vtkRPScene> scene;
  SceneTransferReport read, written;
  std::string error;
  bool didRead = false, didWrite = false;
  if (!IsSceneFileName(input) || !IsSceneFileName(output))
    error = "a scene converts only to a scene: use " + SceneFileExtensions()[0] + ", .mrml or .mrb on both sides";
  else if (!(didRead = ReadSceneFile(input, scene, read))) error = read.Error;
  else if (!(didWrite = WriteSceneFile(scene, output, written))) error = written.Error;
  else if (!read.FirstProblem().empty()) error = "could not load " + read.FirstProblem();
  else if (!written.FirstProblem().empty()) error = "could not write " + written.FirstProblem();
  if (json) {
    nlohmann::json doc = {{"ok", error.empty()}, {"input", input}, {"output", output}};
    if (!error.empty()) doc["error"] = error;
    if (didRead) doc["read"] = ReportJson(input, read);
    if (didWrite) doc["written"] = ReportJson(output, written);
    out << doc.dump(2) << "\n";
  } else {
    for (const auto& warning : read.Warnings) err << "roboplan convert: warning: " << warning << "\n";
    for (const auto& warning : written.Warnings) err << "roboplan convert: warning: " << warning << "\n";
    if (didRead) out << "read " << input << ": " << CountsText(read.NodesByType) << "\n";
    if (didWrite) out << "wrote " << output << ": " << CountsText(written.NodesByType) << "\n";
  }
  if (error.empty()) return 0;
  err << "roboplan convert: " << error << "\n";
  return 1;
}

}  // namespace rp
