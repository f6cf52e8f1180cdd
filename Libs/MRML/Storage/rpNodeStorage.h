#pragma once
// File storage for scene nodes (the storage nodes of Slicer, as plain classes). Each format
// lives in its own rp*IO.cxx and is listed in rpStorageFormats.cxx; the scene reader and writer
// and `roboplan <data files>` find the right one by node class or file extension.
#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

class vtkRPNode;
class vtkRPScene;

namespace rp {

class NodeStorage {
 public:
  virtual ~NodeStorage() = default;
  /// Short name for messages, e.g. "NRRD volume".
  virtual std::string Description() const = 0;
  /// True if this storage writes and reads nodes of this class.
  virtual bool CanHandle(const vtkRPNode* node) const = 0;
  /// Extensions this storage reads, with the dot, longest first (".seg.nrrd" before ".nrrd").
  virtual std::vector<std::string> Extensions() const = 0;
  /// Extension used when saving a scene.
  virtual std::string DefaultExtension() const { return this->Extensions().front(); }
  /// Node class a file of this kind loads into (e.g. "vtkRPModelNode").
  virtual std::string NodeClassForFiles() const = 0;
  /// Node class this very file loads into, when its content decides (a .mrk.json holds a point
  /// list, a line or a plane); by default NodeClassForFiles(). "" with `error` for a file that
  /// cannot be told.
  virtual std::string NodeClassForFile(const std::string& path, std::string& error) const {
    (void)path, (void)error;
    return this->NodeClassForFiles();
  }
  /// Higher wins when several storages handle a node or an extension (".seg.nrrd" over ".nrrd").
  virtual int Priority() const { return 0; }

  /// Write/read the node's data. On failure: false, `error` names the file and the problem, and
  /// the node is left as it was (readers read into temporaries first).
  virtual bool Write(vtkRPNode* node, const std::string& path, std::string& error) const = 0;
  virtual bool Read(vtkRPNode* node, const std::string& path, std::string& error) const = 0;
};

/// Registers a storage beside the library's own (rpStorageFormats.h lists those): a module's or
/// another library's, at its owner's start-up.
bool RegisterNodeStorage(std::shared_ptr<NodeStorage> storage);
/// Best storage for a node (by class), or nullptr.
const NodeStorage* FindNodeStorage(const vtkRPNode* node);
/// Best storage for a file name (by extension, case-insensitive), or nullptr.
const NodeStorage* FindNodeStorageForFile(const std::string& path);
std::vector<std::shared_ptr<NodeStorage>> GetNodeStorages();
/// Every extension read for a node class (e.g. "vtkRPScalarVolumeNode"), for file choosers and
/// CLI descriptors.
std::vector<std::string> ExtensionsForNodeClass(const std::string& nodeClass);

/// True if `path` ends with `extension` (case-insensitive).
bool HasExtension(const std::string& path, const std::string& extension);
/// A node name as a file name: letters, digits, '-' and '_' kept, anything else '_' ("node" if empty).
std::string DataFileBaseName(const std::string& name);

/// Loads a data file into a new node added to `scene` (name from the file name). Returns the
/// node, or nullptr with `error` set; the scene is untouched on failure.
vtkRPNode* LoadDataFile(vtkRPScene* scene, const std::string& path, std::string& error);
/// The two halves of LoadDataFile, for reading off the main thread: CreateNodeForFile makes
/// the node the file needs (main thread: it asks the scene's node registry), ReadNodeFile
/// fills it from the file (any thread: the node is in no scene yet; name from the file name).
vtkSmartPointer<vtkRPNode> CreateNodeForFile(vtkRPScene* scene, const std::string& path, std::string& error);
bool ReadNodeFile(vtkRPNode* node, const std::string& path, std::string& error);
/// Saves one node's data to `path` (format from the extension), atomically.
bool SaveDataFile(vtkRPNode* node, const std::string& path, std::string& error);

}  // namespace rp
