#include "rpSceneIO.h"

#include <cctype>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>
#include <vtkSmartPointer.h>

#include "rpAtomicFile.h"
#include "rpNodeStorage.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace rp {
namespace {

// File-name-safe version of a node name.
std::string SafeFileName(const std::string& name) {
  std::string out;
  for (char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("node") : out;
}

}  // namespace

bool SaveScene(vtkRPScene* scene, const std::string& sceneFile, std::string& error) {
  const fs::path scenePath(sceneFile);
  const fs::path folder = scenePath.has_parent_path() ? scenePath.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) {
    error = "cannot create folder '" + folder.string() + "': " + ec.message();
    return false;
  }
  json document;
  document["format"] = "RoboPlan scene";
  document["version"] = SceneFileFormatVersion;
  document["coordinateSystem"] = "RAS";
  document["units"] = "mm";
  json nodes = json::array();
  std::set<std::string> usedFileNames;
  for (vtkRPNode* node : scene->GetNodes()) {
    json entry;
    entry["class"] = node->GetClassName();
    entry["id"] = node->GetID();
    entry["name"] = node->GetName();
    vtkRPNode::PropertyMap properties;
    node->WriteProperties(properties);
    entry["properties"] = properties;
    entry["attributes"] = node->GetAttributes();
    json references = json::object();
    for (const auto& role : node->GetReferenceRoles()) {
      json ids = json::array();
      for (int n = 0; n < node->GetNumberOfNodeReferences(role); ++n) ids.push_back(node->GetNodeReferenceID(role, n));
      references[role] = ids;
    }
    entry["references"] = references;
    if (const NodeStorage* storage = FindNodeStorage(node)) {
      std::string fileName = SafeFileName(node->GetName()) + storage->DefaultExtension();
      for (int n = 2; usedFileNames.count(fileName); ++n) {
        fileName = SafeFileName(node->GetName()) + "_" + std::to_string(n) + storage->DefaultExtension();
      }
      usedFileNames.insert(fileName);
      std::string writeError;
      if (!storage->Write(node, (folder / fileName).string(), writeError)) {
        error = "saving node '" + node->GetName() + "' failed: " + writeError;
        return false;
      }
      entry["dataFile"] = fileName;
    }
    nodes.push_back(entry);
  }
  document["nodes"] = nodes;
  return WriteFileAtomically(sceneFile, document.dump(2) + "\n", error);
}

SceneLoadReport LoadScene(vtkRPScene* scene, const std::string& sceneFile) {
  SceneLoadReport report;
  std::string text;
  if (!ReadFile(sceneFile, text, report.Error)) {
    report.Ok = false;
    return report;
  }
  const json document = json::parse(text, nullptr, false);
  if (document.is_discarded() || !document.is_object()) {
    report.Ok = false;
    report.Error = "'" + sceneFile + "' is not a valid JSON scene file";
    return report;
  }
  if (document.value("format", "") != "RoboPlan scene") {
    report.Ok = false;
    report.Error = "'" + sceneFile + "' is not a RoboPlan scene (missing \"format\": \"RoboPlan scene\")";
    return report;
  }
  const int version = document.value("version", 0);
  if (version < 1 || version > SceneFileFormatVersion) {
    report.Ok = false;
    report.Error = "'" + sceneFile + "' has scene format version " + std::to_string(version) +
                   "; this program reads versions 1 to " + std::to_string(SceneFileFormatVersion);
    return report;
  }
  const fs::path folder = fs::path(sceneFile).has_parent_path() ? fs::path(sceneFile).parent_path() : fs::path(".");
  std::vector<vtkSmartPointer<vtkRPNode>> loaded;
  std::set<std::string> skippedIDs;
  const json nodeEntries = document.value("nodes", json::array());
  for (const json& entry : nodeEntries) {
    const std::string className = entry.value("class", "");
    const std::string name = entry.value("name", "");
    vtkSmartPointer<vtkRPNode> node = scene->CreateNodeByClass(className);
    if (!node) {
      report.Problems.push_back("node '" + name + "': unknown node class '" + className + "' (is its module loaded?)");
      skippedIDs.insert(entry.value("id", ""));
      continue;
    }
    node->SetIDInternal(entry.value("id", ""));
    node->SetName(name);
    try {
      node->ReadProperties(entry.value("properties", vtkRPNode::PropertyMap{}));
      const auto attributes = entry.value("attributes", std::map<std::string, std::string>{});
      for (const auto& [key, value] : attributes) node->SetAttribute(key, value);
      const json references = entry.value("references", json::object());
      for (const auto& [role, ids] : references.items()) {
        for (const auto& id : ids) node->AddNodeReferenceID(role, id.get<std::string>());
      }
    } catch (const std::exception& e) {
      report.Problems.push_back("node '" + name + "': malformed entry (" + e.what() + ")");
      skippedIDs.insert(node->GetID());
      continue;
    }
    if (entry.contains("dataFile")) {
      const std::string fileName = entry["dataFile"].get<std::string>();
      const std::string path = (folder / fileName).string();
      const NodeStorage* storage = FindNodeStorageForFile(path);
      std::string readError;
      if (!fs::exists(path)) {
        readError = "file is missing";
      } else if (!storage) {
        readError = "no reader for this file type";
      } else if (!storage->Read(node, path, readError)) {
        if (readError.empty()) readError = "could not be read";
      }
      if (!readError.empty()) {
        report.Problems.push_back(fileName + " (" + name + "): " + readError);
        skippedIDs.insert(node->GetID());
        continue;
      }
    }
    loaded.push_back(node);
  }
  // References to nodes that could not be loaded are dropped rather than left dangling.
  for (auto& node : loaded) {
    for (const auto& id : skippedIDs) node->RemoveReferencesTo(id);
  }
  scene->Import(loaded);
  report.NodesLoaded = static_cast<int>(loaded.size());
  return report;
}

}  // namespace rp
