#pragma once
// 3D Slicer's scene files with our own code: the MRML scene (.mrml, XML) and the Medical Reality
// Bundle (.mrb, a zip of a .mrml and its data files). Reading maps Slicer's node types onto ours
// (Volume/LabelMapVolume -> vtkRPScalarVolumeNode, Model, LinearTransform, Segmentation,
// MarkupsFiducial -> vtkRPFiducialListNode, Slice + SliceComposite -> vtkRPSliceNode, Layout),
// with their display and storage nodes, both link forms (`references="role:id id;"` and the older
// `displayNodeRef`/`storageNodeRef`/`transformNodeRef`), URL-encoded (also twice) file names
// relative to the scene file, and the data files read by the per-format storages of
// rpNodeStorage.h. Writing gives every node of ours the Slicer nodes it needs to be shown as we
// show it (display, storage, data file under Data/); fields Slicer has no place for (tissue class,
// haptic flag) and our own node attributes travel as MRML node attributes, which Slicer keeps.
// What cannot be loaded is reported, never fatal: node types we do not have (one warning by tag
// and count), a missing or unreadable data file (named; the rest loads, as in Slicer), a
// transform that is its own ancestor (the link is dropped). The scene given is only added to.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

class vtkRPScene;

namespace rp {

/// What a scene read or write did, for messages and `roboplan convert --json`.
struct SceneTransferReport {
  bool Ok = true;     // false: nothing was read / written (Error says why)
  std::string Error;  // the first thing that could not be done, when !Ok
  std::map<std::string, int> NodesByType;  // read: our node tags loaded; write: MRML tags written
  std::vector<std::string> Files;          // data files read or written (relative to the scene)
  struct Skip {
    std::string What, Why;  // e.g. "Data/CT.nrrd (node 'CT')", "file is missing"
  };
  std::vector<Skip> Skipped;          // what was left out, and why (each also a problem)
  std::vector<std::string> Warnings;  // e.g. the node types we do not have, by tag and count
  /// The first skipped item as one line, "" when nothing was skipped.
  std::string FirstProblem() const;
};

struct MrmlReadOptions {
  /// Bytes a bundle may unpack to; 0: the memory check's figure (rp::AvailableMemoryBytes).
  uint64_t MaxBundleBytes = 0;
};

/// Reads a .mrml scene file into `scene` (added to; existing nodes are kept; IDs that clash are
/// renamed). Returns report.Ok.
bool ReadMrmlScene(const std::string& path, vtkRPScene* scene, SceneTransferReport& report,
                   const MrmlReadOptions& options = {});
/// Reads a .mrb bundle: unpacked into a temporary folder (removed afterwards), its main scene is
/// the .mrml nearest the zip root. Entries that leave the folder, links, and bundles larger than
/// the memory check allows are refused before anything is written.
bool ReadMrmlBundle(const std::string& path, vtkRPScene* scene, SceneTransferReport& report,
                    const MrmlReadOptions& options = {});

/// Writes `scene` as a .mrml file with its data files under Data/ beside it.
bool WriteMrmlScene(vtkRPScene* scene, const std::string& path, SceneTransferReport& report);
/// Writes `scene` as a .mrb bundle (built in a temporary folder, then renamed over `path`).
bool WriteMrmlBundle(vtkRPScene* scene, const std::string& path, SceneTransferReport& report);

}  // namespace rp
