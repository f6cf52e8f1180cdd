#include "rpSceneIO.h"

#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpAtomicFile.h"
#include "rpNodeStorage.h"
#include "rpSceneDataFiles.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// The files a scene file owns: the data files it names and those it lists as its own (empty when
// there is none or it cannot be read).
std::set<std::string> OwnedFilesOf(const std::string& sceneFile) {
  std::set<std::string> files;
  std::string text, error;
  SceneFileDocument document;
  std::error_code ec;
  if (!fs::exists(sceneFile, ec) || !ReadFile(sceneFile, text, error) || !ParseSceneFile(text, sceneFile, document, error))
    return files;
  for (const SceneFileNode& node : document.Nodes)
    if (!node.DataFile.empty()) files.insert(node.DataFile);
  files.insert(document.OwnedFiles.begin(), document.OwnedFiles.end());
  return files;
}

// When the disk is (nearly) full, says so first: the writers' own messages rarely do.
std::string DiskFullNote(const fs::path& folder) {
  std::error_code ec;
  const fs::space_info space = fs::space(folder, ec);
  if (ec || space.available >= (1u << 20)) return "";
  return "no space left on the disk holding '" + folder.string() + "' (" + std::to_string(space.available) +
         " bytes free); ";
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
  SceneDataFiles files(folder, OwnedFilesOf(sceneFile));
  files.RemoveInterruptedSaves("");
  SceneFileDocument document;
  for (vtkRPNode* node : scene->GetNodes()) {
    SceneFileNode entry;
    entry.Class = node->GetClassName();
    entry.ID = node->GetID();
    entry.Name = node->GetName();
    node->WriteProperties(entry.Properties);
    entry.Attributes = node->GetAttributes();
    for (const auto& role : node->GetReferenceRoles()) {
      std::vector<std::string> ids;
      for (int n = 0; n < node->GetNumberOfNodeReferences(role); ++n) ids.push_back(node->GetNodeReferenceID(role, n));
      entry.References.emplace_back(role, std::move(ids));
    }
    if (const NodeStorage* storage = FindNodeStorage(node)) {
      entry.DataFile = files.Claim("", DataFileBaseName(node->GetName()), storage->DefaultExtension());
      std::string writeError;
      if (!storage->Write(node, files.StagingPath(entry.DataFile), writeError)) {
        error = "saving node '" + node->GetName() + "' failed: " + DiskFullNote(folder) + writeError;
        return false;  // `files` removes what was written: nothing names it
      }
    }
    document.Nodes.push_back(std::move(entry));
  }
  const auto text = [&document](const std::map<std::string, std::string>& names, const std::vector<std::string>& owned) {
    SceneFileDocument version = document;
    for (SceneFileNode& node : version.Nodes)
      if (!node.DataFile.empty()) node.DataFile = names.at(node.DataFile);
    version.OwnedFiles = owned;
    return FormatSceneFile(version);
  };
  std::string commitError;
  if (files.Commit(sceneFile, text, commitError)) return true;
  error = (files.Committed() ? "" : DiskFullNote(folder)) + commitError;
  return false;
}

SceneLoadReport LoadScene(vtkRPScene* scene, const std::string& sceneFile) {
  SceneLoadReport report;
  std::string text;
  if (!ReadFile(sceneFile, text, report.Error)) {
    report.Ok = false;
    return report;
  }
  SceneFileDocument document;
  if (!ParseSceneFile(text, sceneFile, document, report.Error)) {
    report.Ok = false;
    return report;
  }
  const fs::path folder = fs::path(sceneFile).has_parent_path() ? fs::path(sceneFile).parent_path() : fs::path(".");
  std::vector<vtkSmartPointer<vtkRPNode>> loaded;
  std::set<std::string> skippedIDs;
  for (const SceneFileNode& entry : document.Nodes) {
    if (!entry.Problem.empty()) {
      report.Problems.push_back("node '" + entry.Name + "': " + entry.Problem);
      skippedIDs.insert(entry.ID);
      continue;
    }
    vtkSmartPointer<vtkRPNode> node = scene->CreateNodeByClass(entry.Class);
    if (!node) {
      report.Problems.push_back("node '" + entry.Name + "': unknown node class '" + entry.Class +
                                "' (is its module loaded?)");
      skippedIDs.insert(entry.ID);
      continue;
    }
    node->SetIDInternal(entry.ID);
    node->SetName(entry.Name);
    try {
      node->ReadProperties(entry.Properties);
    } catch (const std::exception& e) {
      report.Problems.push_back("node '" + entry.Name + "': malformed entry (" + e.what() + ")");
      skippedIDs.insert(node->GetID());
      continue;
    }
    for (const auto& [key, value] : entry.Attributes) node->SetAttribute(key, value);
    for (const auto& [role, ids] : entry.References)
      for (const auto& id : ids) node->AddNodeReferenceID(role, id);
    if (!entry.DataFile.empty()) {
      const std::string path = (folder / entry.DataFile).string();
      const NodeStorage* storage = FindNodeStorageForFile(path);
      std::string readError;
      std::error_code ec;
      if (!fs::is_regular_file(path, ec)) {
        readError = "file is missing";
      } else if (!storage) {
        readError = "no reader for this file type";
      } else if (!storage->Read(node, path, readError)) {
        if (readError.empty()) readError = "could not be read";
      }
      if (!readError.empty()) {
        report.Problems.push_back(entry.DataFile + " (" + entry.Name + "): " + readError);
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
