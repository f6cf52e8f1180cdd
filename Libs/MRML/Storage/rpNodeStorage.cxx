#include "rpNodeStorage.h"

#include <algorithm>
#include <cctype>
#include <mutex>

#include "rpAtomicFile.h"
#include "rpStorageFormats.h"
#include "vtkRPNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "rpStrings.h"

namespace rp {
namespace {
// The library's own storages (rpStorageFormats.cxx), then what others register.
struct Registry {
  std::mutex Mutex;
  std::vector<std::shared_ptr<NodeStorage>> Storages = BuiltInNodeStorages();
};
Registry& GetRegistry() {
  static Registry registry;
  return registry;
}

std::string BaseNameWithoutExtension(const std::string& path, const NodeStorage& storage) {
  const auto slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  for (const auto& ext : storage.Extensions()) {
    if (HasExtension(base, ext)) return base.substr(0, base.size() - ext.size());
  }
  return base;
}
}  // namespace

bool HasExtension(const std::string& path, const std::string& extension) {
  if (path.size() < extension.size()) return false;
  return Lower(path.substr(path.size() - extension.size())) == Lower(extension);
}

std::string DataFileBaseName(const std::string& name) {
  std::string out;
  for (char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("node") : out;
}

bool RegisterNodeStorage(std::shared_ptr<NodeStorage> storage) {
  Registry& registry = GetRegistry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  registry.Storages.push_back(std::move(storage));
  return true;
}

std::vector<std::shared_ptr<NodeStorage>> GetNodeStorages() {
  Registry& registry = GetRegistry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  return registry.Storages;
}

std::vector<std::string> ExtensionsForNodeClass(const std::string& nodeClass) {
  std::vector<std::string> extensions;
  for (const auto& storage : GetNodeStorages()) {
    if (storage->NodeClassForFiles() != nodeClass) continue;
    for (const auto& ext : storage->Extensions())
      if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) extensions.push_back(ext);
  }
  return extensions;
}

const NodeStorage* FindNodeStorage(const vtkRPNode* node) {
  const NodeStorage* best = nullptr;
  for (const auto& storage : GetNodeStorages()) {
    if (storage->CanHandle(node) && (!best || storage->Priority() > best->Priority())) best = storage.get();
  }
  return best;
}

const NodeStorage* FindNodeStorageForFile(const std::string& path) {
  const NodeStorage* best = nullptr;
  size_t bestLength = 0;
  for (const auto& storage : GetNodeStorages()) {
    for (const auto& ext : storage->Extensions()) {
      if (!HasExtension(path, ext)) continue;
      // The longest matching extension wins (".seg.nrrd" over ".nrrd"), then priority.
      if (!best || ext.size() > bestLength || (ext.size() == bestLength && storage->Priority() > best->Priority())) {
        best = storage.get();
        bestLength = ext.size();
      }
    }
  }
  return best;
}

vtkSmartPointer<vtkRPNode> CreateNodeForFile(vtkRPScene* scene, const std::string& path, std::string& error) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage) {
    error = "'" + path + "': no reader for this file type";
    return nullptr;
  }
  const std::string nodeClass = storage->NodeClassForFile(path, error);
  if (nodeClass.empty()) return nullptr;
  vtkSmartPointer<vtkRPNode> node = scene->CreateNodeByClass(nodeClass);
  if (!node) error = "'" + path + "': node class " + nodeClass + " is not registered in the scene";
  return node;
}

bool ReadNodeFile(vtkRPNode* node, const std::string& path, std::string& error) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage) {
    error = "'" + path + "': no reader for this file type";
    return false;
  }
  if (!storage->Read(node, path, error)) return false;
  if (auto* volume = vtkRPScalarVolumeNode::SafeDownCast(node)) volume->SetWindowLevelFromScalarRange();
  node->SetName(BaseNameWithoutExtension(path, *storage));
  return true;
}

vtkRPNode* LoadDataFile(vtkRPScene* scene, const std::string& path, std::string& error) {
  vtkSmartPointer<vtkRPNode> node = CreateNodeForFile(scene, path, error);
  if (!node || !ReadNodeFile(node, path, error)) return nullptr;
  return scene->AddNode(node);
}

bool SaveDataFile(vtkRPNode* node, const std::string& path, std::string& error) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage || !storage->CanHandle(node)) {
    error = "'" + path + "': cannot save a " + node->GetClassName() + " in this format";
    return false;
  }
  return storage->Write(node, path, error);
}

}  // namespace rp
