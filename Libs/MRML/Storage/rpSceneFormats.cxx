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

SceneConversion ConvertScene(const std::string& input, const std::string& output) {
  vtkNew<vtkRPScene> scene;
  SceneConversion c;
  if (!IsSceneFileName(input) || !IsSceneFileName(output))
    c.Error = "a scene converts only to a scene: use " + SceneFileExtensions()[0] + ", .mrml or .mrb on both sides";
  else if (!(c.DidRead = ReadSceneFile(input, scene, c.Read))) c.Error = c.Read.Error;
  else if (!(c.DidWrite = WriteSceneFile(scene, output, c.Written))) c.Error = c.Written.Error;
  else if (!c.Read.FirstProblem().empty()) c.Error = "could not load " + c.Read.FirstProblem();
  else if (!c.Written.FirstProblem().empty()) c.Error = "could not write " + c.Written.FirstProblem();
  return c;
}

int ReportSceneConversion(const SceneConversion& c, const std::string& input, const std::string& output, bool json,
                          std::ostream& out, std::ostream& err) {
  if (json) {
    nlohmann::json doc = {{"ok", c.Error.empty()}, {"input", input}, {"output", output}};
    if (!c.Error.empty()) doc["error"] = c.Error;
    if (c.DidRead) doc["read"] = ReportJson(input, c.Read);
    if (c.DidWrite) doc["written"] = ReportJson(output, c.Written);
    out << doc.dump(2) << "\n";
  } else {
    for (const auto& warning : c.Read.Warnings) err << "roboplan convert: warning: " << warning << "\n";
    for (const auto& warning : c.Written.Warnings) err << "roboplan convert: warning: " << warning << "\n";
    if (c.DidRead) out << "read " << input << ": " << CountsText(c.Read.NodesByType) << "\n";
    if (c.DidWrite) out << "wrote " << output << ": " << CountsText(c.Written.NodesByType) << "\n";
  }
  if (c.Error.empty()) return 0;
  err << "roboplan convert: " << c.Error << "\n";
  return 1;
}

int ConvertSceneFile(const std::string& input, const std::string& output, bool json, std::ostream& out,
                     std::ostream& err) {
  return ReportSceneConversion(ConvertScene(input, output), input, output, json, out, err);
}

}  // namespace rp
