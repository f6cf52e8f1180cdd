#include "rpSceneIO.h"

#include <cctype>
#include <filesystem>
#include <set>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpAtomicFile.h"
#include "rpNodeStorage.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// The data files a scene file names (empty when there is none or it cannot be read).
std::set<std::string> DataFilesOf(const std::string& sceneFile) {
  std::set<std::string> files;
  std::string text, error;
  SceneFileDocument document;
  std::error_code ec;
  if (!fs::exists(sceneFile, ec) || !ReadFile(sceneFile, text, error) || !ParseSceneFile(text, sceneFile, document, error))
    return files;
  for (const SceneFileNode& node : document.Nodes)
    if (!node.DataFile.empty()) files.insert(node.DataFile);
  return files;
}

// A data file name this program may remove: a plain name in the scene's folder.
bool IsPlainFileName(const std::string& name) {
  return !name.empty() && name.find('/') == std::string::npos && name != "." && name != "..";
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
  RemoveStaleTemporaryFiles(folder.string());  // left by a save that was killed
  // What the scene file being replaced uses is never written over before the commit.
  const std::set<std::string> previous = DataFilesOf(sceneFile);
  std::set<std::string> used;
  std::vector<fs::path> written;
  auto fail = [&](const std::string& what, const std::string& why) {
    error = what + DiskFullNote(folder) + why;
    for (const fs::path& file : written) fs::remove(file, ec);  // not referenced by anything
    return false;
  };
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
      const std::string base = DataFileBaseName(node->GetName()), extension = storage->DefaultExtension();
      std::string fileName = base + extension;
      for (int n = 2; used.count(fileName) || previous.count(fileName); ++n)
        fileName = base + "_" + std::to_string(n) + extension;
      used.insert(fileName);
      std::string writeError;
      if (!storage->Write(node, (folder / fileName).string(), writeError))
        return fail("saving node '" + node->GetName() + "' failed: ", writeError);
      written.push_back(folder / fileName);
      entry.DataFile = fileName;
    }
    document.Nodes.push_back(std::move(entry));
  }
  std::string writeError;
  if (!WriteFileAtomically(sceneFile, FormatSceneFile(document), writeError)) return fail("", writeError);
  // Committed: the previous version's data files that this one does not name are not used by it.
  for (const std::string& file : previous) {
    if (!used.count(file) && IsPlainFileName(file)) fs::remove(folder / file, ec);
  }
  return true;
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
