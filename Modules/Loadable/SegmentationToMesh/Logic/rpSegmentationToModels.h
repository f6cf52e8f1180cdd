#pragma once
// Segmentation → model nodes: per segment a display mesh and (optionally) a coarser haptic mesh,
// each with its own level-of-detail target; both carry the segment's tissue class and colour.
#include <functional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpLabelmapToMesh.h"
#include "rpMeshLevelOfDetail.h"
#include "rpProgress.h"

class vtkRPModelNode;
class vtkRPScene;
class vtkRPSegmentationNode;

namespace rp {

struct ModelBuildOptions {
  MeshOptions Display;
  LevelOfDetail DisplayLOD;
  bool MakeHaptic = true;
  MeshOptions Haptic;
  LevelOfDetail HapticLOD = {20000, 0.0};
  std::vector<std::string> SegmentIDs;  // empty = every segment
};

struct SegmentModels {
  std::string SegmentID, Name, TissueClass;
  bool Ok = false;
  std::string Error;  // why this segment has no model (empty segment, ...)
  MeshStats Display, Haptic;
  vtkSmartPointer<vtkRPModelNode> DisplayModel, HapticModel;
};

/// Builds the models of the requested segments; adds them to `scene` when given. A segment that
/// fails (e.g. empty) is reported in its entry and the others are still built. `done` is called
/// with a segment's entry as soon as its display model is built (HapticModel still empty) and
/// again when its haptic model is, e.g. to write each file while the rest meshes: a model's
/// mesh is only read here after its call.
std::vector<SegmentModels> BuildSegmentModels(vtkRPSegmentationNode* segmentation, const ModelBuildOptions& options,
                                              vtkRPScene* scene = nullptr, const ProgressCallback& progress = nullptr,
                                              const std::function<void(const SegmentModels&)>& done = nullptr);

}  // namespace rp
