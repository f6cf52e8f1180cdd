#pragma once
// One way to open a path: `rp::LoadPath(scene, path, options)` reads a file or a folder into
// nodes and adds them to the scene. Every command, the viewer and the demo open data through it,
// so a format is known in one place and every caller gets it (DICOM `--series`, DICOMDIR, scene
// files...). Formats are DataReaders in a registry, as PLUS's device factory and Slicer's
// qSlicerIO: one class and one registration per format. The node formats of the node-storage
// registry (rpNodeStorage.h: NRRD, NIfTI, .seg.nrrd, models, markups, transforms) are one reader
// here, so their extensions stay listed once, in their storages.
//
// Add a reader in minutes (a new file beside the format's code, e.g. rpMyFormatReader.cxx):
//
//   namespace {
//   class MyFormatReader : public rp::DataReader {
//    public:
//     std::string Description() const override { return "My format"; }
//     bool CanRead(const std::string& path) const override { return rp::HasExtension(path, ".my"); }
//     bool Read(const std::string& path, const rp::ReadOptions& options, vtkRPScene* scene,
//               rp::LoadResult& result) const override {
//       auto node = scene->CreateNodeByClass("vtkRPModelNode");  // a factory only: do not add it
//       ... fill node, or set result.Error and return false ...
//       result.Nodes.push_back(node);
//       return true;
//     }
//   };
//   }  // namespace
//   std::shared_ptr<DataReader> MakeMyFormatReader() { return std::make_shared<MyFormatReader>(); }
//
// then one line in BuiltInDataReaders (rpStorageFormats.cxx, where every reader of this library is
// listed; no static registrars), and its Description in Testing/Registration/rpRegistrationTest.cxx.
// A reader of another library registers in that library's Register...() which its hosts call at
// start-up (see rpImagingReaders.h).
// Readers registered today: "RoboPlan scene" (.rpscene, rpSceneFileReader.cxx), "3D Slicer scene"
// (.mrml, .mrb: rpMrmlDataReader.cxx), "Node file" (every
// node storage, rpDataLoader.cxx), "DICOM" (a folder or DICOMDIR read whole: every image series,
// SEG and RTSTRUCT; a DICOM file: Libs/Imaging/rpDicomDataReader.cxx), "DICOM SEG / RTSTRUCT"
// (such a file: rpDicomSegmentationDataReader.cxx).
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkSmartPointer.h>

#include "rpNodeStorage.h"
#include "rpProgress.h"

class vtkRPNode;
class vtkRPScene;

namespace rp {

/// How to read (all optional; a reader ignores what does not apply to it).
struct ReadOptions {
  /// DICOM: the series to read when the folder holds several: a SeriesInstanceUID, or
  /// "<SeriesInstanceUID>#<n>" for one stack of a series (see `roboplan dicom`).
  std::string Series;
  /// DICOM: resample a series with a missing slice or uneven spacing onto a regular grid.
  bool ResampleIrregularSpacing = false;
  /// Progress of a long read (fraction 0..1, message); may throw to cancel.
  ProgressCallback Progress;
};

/// What a read produced.
struct LoadResult {
  bool Ok = false;
  std::string Error;                               // when !Ok: names the path and the problem
  std::vector<std::string> Warnings;               // non-fatal notes (e.g. a skipped node)
  std::vector<vtkSmartPointer<vtkRPNode>> Nodes;   // the nodes read (LoadPath adds them; empty
                                                   // for readers that ReadsIntoScene)
  std::string Reader;                              // Description() of the reader that read it
  nlohmann::json Details = nlohmann::json::object();  // reader-specific facts, for --json
};

class DataReader {
 public:
  virtual ~DataReader() = default;
  /// Short name for messages and listings, e.g. "DICOM".
  virtual std::string Description() const = 0;
  /// True if this reader reads `path` (by extension, folder content or file magic). Cheap: it
  /// may look at the file system, not read whole files.
  virtual bool CanRead(const std::string& path) const = 0;
  /// Higher wins when several readers can read a path.
  virtual int Priority() const { return 0; }
  /// False (the default): Read puts new nodes, in no scene, into result.Nodes and uses `scene`
  /// only as a node factory (CreateNodeByClass), so it may run on a worker thread; LoadPath adds
  /// the nodes. True: Read fills the scene itself (scene files) on the main thread.
  virtual bool ReadsIntoScene() const { return false; }
  /// Reads `path`. On failure: false and result.Error set; the scene is as it was (readers that
  /// read into the scene leave what was loaded before).
  virtual bool Read(const std::string& path, const ReadOptions& options, vtkRPScene* scene,
                    LoadResult& result) const = 0;
};

/// Registers a reader beside the library's own (rpStorageFormats.h lists those): another library's
/// or a module's, at its owner's start-up (as RegisterImagingReaders).
bool RegisterDataReader(std::shared_ptr<DataReader> reader);
/// Every registered reader, in registration order.
std::vector<std::shared_ptr<DataReader>> GetDataReaders();
/// The reader for `path`: of those that CanRead it, the highest Priority; nullptr if none.
const DataReader* FindDataReader(const std::string& path);

/// Reads `path` with its reader; the nodes are not added to the scene unless the reader
/// ReadsIntoScene (then it is the main thread's call). Safe on a worker thread otherwise.
LoadResult ReadPath(vtkRPScene* scene, const std::string& path, const ReadOptions& options = {});
/// The same with the reader FindDataReader(path) returned (nullptr: the "no reader" error), for a
/// caller that looked it up already: a folder's lookup may look into every file in it.
LoadResult ReadPath(vtkRPScene* scene, const std::string& path, const DataReader* reader,
                    const ReadOptions& options = {});
/// Reads `path` and adds the nodes to `scene` (in result.Nodes). On failure the scene is as it was.
LoadResult LoadPath(vtkRPScene* scene, const std::string& path, const ReadOptions& options = {});
/// Adds the nodes a read produced (those not in a scene yet): one as vtkRPScene::AddNode does,
/// several in one vtkRPScene::Import, so references among them (a DICOM segmentation to the
/// volume it lies on) follow their IDs and observers see them arrive together. LoadPath and
/// the viewer's background read add nodes this way.
void AddReadNodes(vtkRPScene* scene, std::vector<vtkSmartPointer<vtkRPNode>>& nodes);
/// For commands that take one data file or folder: LoadPath, then the one node it added, or
/// nullptr with result.Error set (also for a scene file, which is then not read, and for a path
/// that holds several objects, e.g. a DICOM study: the error names them and the IDs `--series`
/// takes; the scene is untouched then).
vtkRPNode* LoadSingleNode(vtkRPScene* scene, const std::string& path, LoadResult& result,
                          const ReadOptions& options = {});

}  // namespace rp
