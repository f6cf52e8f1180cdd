#pragma once
// The patient data a plan's figures read, taken from scene nodes: the CT and the segmentation as
// samplers in world RAS (their images stay referenced here while the samplers read them), which
// segments are bone, and the bone ranges of materials.json. Bone segments are those whose tissue
// class is a bone of the material table (a drillable tissue); a segmentation with no tissue
// classes at all (a plain labelmap) counts every segment as bone, or the ones named in `boneSegments`.
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpMaterial.h"
#include "rpTissueModel.h"

class vtkImageData;
class vtkRPScalarVolumeNode;
class vtkRPSegmentationNode;

namespace rp {

/// The bone tissues of the table (those with a ctMinHU), highest threshold first, as HU ranges.
std::vector<BoneHURange> BoneRangesOf(const MaterialTable& materials);
/// The lowest ctMinHU: the CT number from which a voxel is bone without a segmentation.
double BoneThresholdOf(const MaterialTable& materials);
/// Whether a tissue class is a bone of the table.
bool IsBoneTissue(const MaterialTable& materials, const std::string& tissueClass);

class PlanningInputs {
 public:
  /// Either node may be null. `boneSegments` (IDs, names or label values) overrides which segments
  /// are bone. False with `error` naming the node and the problem (a volume without voxels, a
  /// segmentation of non-integer voxels, an unknown segment).
  bool Set(vtkRPScalarVolumeNode* ct, vtkRPSegmentationNode* segmentation, const MaterialTable& materials,
           std::string& error, const std::vector<std::string>& boneSegments = {});
  const TissueModel& Tissue() const { return this->Model; }
  /// What counts as bone, in words (for reports).
  const std::string& BoneRule() const { return this->Rule; }

 private:
  vtkSmartPointer<vtkImageData> CTImage, LabelImage;
  TissueModel Model;
  std::string Rule;
};

/// Points a sampler at an image node's voxels in world RAS (its parent transforms applied).
bool SetSampler(VolumeSampler& sampler, vtkImageData* image, const double ijkToWorld[16], std::string& error);

}  // namespace rp
