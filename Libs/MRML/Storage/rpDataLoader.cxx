#include "rpDataLoader.h"

#include <filesystem>
#include <mutex>

#include "rpStorageFormats.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace rp {
namespace {

// The library's own readers (rpStorageFormats.cxx), then what others register (the imaging
// readers: RegisterImagingReaders, called in the Setup of each module that reads DICOM).
struct Registry {
  std::mutex Mutex;
  std::vector<std::shared_ptr<DataReader>> Readers = BuiltInDataReaders();
};
Registry& GetRegistry() {
  static Registry registry;
  return registry;
}

// Every format of the node-storage registry (rpNodeStorage.h) as one reader: a file whose
// extension a storage reads becomes one node of the storage's class.
class NodeFileReader : public DataReader {
 public:
  std::string Description() const override { return "Node file"; }
  bool CanRead(const std::string& path) const override {
    std::error_code ec;
    return !std::filesystem::is_directory(path, ec) && FindNodeStorageForFile(path) != nullptr;
  }
  int Priority() const override { return 10; }
  bool Read(const std::string& path, const ReadOptions& options, vtkRPScene* scene,
            LoadResult& result) const override {
    vtkSmartPointer<vtkRPNode> node = CreateNodeForFile(scene, path, result.Error);
    if (!node || !ReadNodeFile(node, path, result.Error)) return false;
    if (options.Progress) options.Progress(1.0, "read");
    result.Details["nodeClass"] = node->GetClassName();
    result.Details["storage"] = FindNodeStorageForFile(path)->Description();
    result.Nodes.push_back(node);
    return true;
  }
};

}  // namespace

std::shared_ptr<DataReader> MakeNodeFileReader() { return std::make_shared<NodeFileReader>(); }

bool RegisterDataReader(std::shared_ptr<DataReader> reader) {
  Registry& registry = GetRegistry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  registry.Readers.push_back(std::move(reader));
  return true;
}

std::vector<std::shared_ptr<DataReader>> GetDataReaders() {
  Registry& registry = GetRegistry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  return registry.Readers;
}

const DataReader* FindDataReader(const std::string& path) {
  const DataReader* best = nullptr;
  for (const auto& reader : GetDataReaders()) {
    if (reader->CanRead(path) && (!best || reader->Priority() > best->Priority())) best = reader.get();
  }
  return best;
}

LoadResult ReadPath(vtkRPScene* scene, const std::string& path, const ReadOptions& options) {
  return ReadPath(scene, path, FindDataReader(path), options);
}

LoadResult ReadPath(vtkRPScene* scene, const std::string& path, const DataReader* reader, const ReadOptions& options) {
  LoadResult result;
  if (!reader) {
    std::error_code ec;
    result.Error = std::filesystem::exists(path, ec) ? "'" + path + "': no reader for this file type"
                                                     : "no such file or folder: " + path;
    return result;
  }
  if (!scene) {
    result.Error = "'" + path + "': no scene to read into";
    return result;
  }
  result.Reader = reader->Description();
  result.Ok = reader->Read(path, options, scene, result);
  if (!result.Ok) result.Nodes.clear();
  return result;
}

void AddReadNodes(vtkRPScene* scene, std::vector<vtkSmartPointer<vtkRPNode>>& nodes) {
  // A reader that reads into the scene has added its nodes already. Nodes with IDs (those that
  // may be referenced) go in one import; nodes without one are added one by one, as Import gives
  // every node without an ID the same new one.
  std::vector<vtkSmartPointer<vtkRPNode>> withIDs;
  for (const auto& node : nodes)
    if (!node->GetScene() && !node->GetID().empty()) withIDs.push_back(node);
  if (withIDs.size() > 1) scene->Import(withIDs);
  for (auto& node : nodes)
    if (!node->GetScene()) node = scene->AddNode(node);
}

LoadResult LoadPath(vtkRPScene* scene, const std::string& path, const ReadOptions& options) {
  LoadResult result = ReadPath(scene, path, options);
  if (result.Ok) AddReadNodes(scene, result.Nodes);
  return result;
}

namespace {

// "'path' holds 2 objects: CT \"knee\" (1.2.3), SEG \"bones\" (1.2.4); choose one (--series <ID>)"
// from what the reader listed (Details "objects"), else the nodes' names.
std::string SeveralNodesError(const std::string& path, const LoadResult& result) {
  std::string list;
  const nlohmann::json& objects = result.Details.contains("objects") ? result.Details["objects"] : nlohmann::json();
  if (objects.is_array() && objects.size() == result.Nodes.size()) {
    for (const auto& o : objects) {
      std::string kind = o.value("modality", std::string());  // an image's modality, else the object's kind
      if (kind.empty()) kind = o.value("kind", std::string());
      list += (list.empty() ? "" : ", ") + kind + " \"" + o.value("description", std::string()) + "\" (" +
              o.value("id", std::string()) + ")";
    }
    return "'" + path + "' holds " + std::to_string(objects.size()) + " objects: " + list +
           "; choose one by its ID (--series <ID>)";
  }
  for (const auto& node : result.Nodes) list += (list.empty() ? "" : ", ") + node->GetName();
  return "'" + path + "' holds " + std::to_string(result.Nodes.size()) + " nodes (" + list + "), not one";
}

}  // namespace

vtkRPNode* LoadSingleNode(vtkRPScene* scene, const std::string& path, LoadResult& result, const ReadOptions& options) {
  const DataReader* reader = FindDataReader(path);
  if (reader && reader->ReadsIntoScene()) {
    result = LoadResult();
    result.Reader = reader->Description();
    result.Error = "'" + path + "' is a " + reader->Description() + " file, not one data file";
    return nullptr;
  }
  result = ReadPath(scene, path, options);
  if (result.Ok && result.Nodes.size() != 1) {
    result.Ok = false;
    result.Error = SeveralNodesError(path, result);
  }
  if (!result.Ok) {
    result.Nodes.clear();
    return nullptr;
  }
  result.Nodes.front() = scene->AddNode(result.Nodes.front());
  return result.Nodes.front();
}

}  // namespace rp
