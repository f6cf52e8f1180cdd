#include "rpPlanningInputs.h"

#include <algorithm>
#include <cmath>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

bool VoxelTypeOf(int vtkType, VoxelType& type) {
  switch (vtkType) {
    case VTK_CHAR: case VTK_SIGNED_CHAR: type = VoxelType::Int8; return true;
    case VTK_UNSIGNED_CHAR: type = VoxelType::UInt8; return true;
    case VTK_SHORT: type = VoxelType::Int16; return true;
    case VTK_UNSIGNED_SHORT: type = VoxelType::UInt16; return true;
    case VTK_INT: type = VoxelType::Int32; return true;
    case VTK_UNSIGNED_INT: type = VoxelType::UInt32; return true;
    case VTK_LONG: type = sizeof(long) == 8 ? VoxelType::Int64 : VoxelType::Int32; return true;
    case VTK_UNSIGNED_LONG: type = sizeof(long) == 8 ? VoxelType::UInt64 : VoxelType::UInt32; return true;
    case VTK_LONG_LONG: case VTK_ID_TYPE: type = VoxelType::Int64; return true;
    case VTK_UNSIGNED_LONG_LONG: type = VoxelType::UInt64; return true;
    case VTK_FLOAT: type = VoxelType::Float32; return true;
    case VTK_DOUBLE: type = VoxelType::Float64; return true;
    default: return false;
  }
}

void ImageToWorld(vtkRPImageNode* node, double m[16]) {
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld;
  node->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, node->GetIJKToRASMatrix(), ijkToWorld);
  vtkMatrix4x4::DeepCopy(m, ijkToWorld);
}

}  // namespace

std::vector<BoneHURange> BoneRangesOf(const MaterialTable& materials) {
  std::vector<BoneHURange> ranges;
  for (const Material& m : materials.Materials())
    if (m.Drillable() && std::isfinite(m.CTMinHU)) ranges.push_back({m.Tissue, m.CTMinHU, HUGE_VAL});
  std::sort(ranges.begin(), ranges.end(), [](const BoneHURange& a, const BoneHURange& b) { return a.MinHU > b.MinHU; });
  for (size_t i = 1; i < ranges.size(); ++i) ranges[i].MaxHU = ranges[i - 1].MinHU;
  return ranges;
}

double BoneThresholdOf(const MaterialTable& materials) {
  const auto ranges = BoneRangesOf(materials);
  return ranges.empty() ? 100.0 : ranges.back().MinHU;
}

bool IsBoneTissue(const MaterialTable& materials, const std::string& tissueClass) {
  const int index = tissueClass.empty() ? -1 : materials.Find(tissueClass);
  return index >= 0 && materials.Materials()[static_cast<size_t>(index)].Drillable();
}

bool SetSampler(VolumeSampler& sampler, vtkImageData* image, const double ijkToWorld[16], std::string& error) {
  VoxelType type;
  if (!image || image->GetNumberOfPoints() == 0 || image->GetNumberOfScalarComponents() != 1 ||
      !VoxelTypeOf(image->GetScalarType(), type)) {
    error = "it has no single-component voxels of a number type";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  return sampler.Set(image->GetScalarPointer(), type, dims, ijkToWorld, error);
}

bool PlanningInputs::Set(vtkRPScalarVolumeNode* ct, vtkRPSegmentationNode* segmentation, const MaterialTable& materials,
                         std::string& error, const std::vector<std::string>& boneSegments) {
  TissueModel model;
  model.BoneRanges = BoneRangesOf(materials);
  model.BoneThresholdHU = BoneThresholdOf(materials);
  double m[16];
  if (ct) {
    ImageToWorld(ct, m);
    if (!SetSampler(model.CT, ct->GetImageData(), m, error)) {
      error = "the volume '" + ct->GetName() + "' cannot be sampled: " + error;
      return false;
    }
  }
  std::string rule = "CT at or above " + std::to_string(static_cast<int>(model.BoneThresholdHU)) +
                     " HU (the lowest ctMinHU of materials.json)";
  if (segmentation) {
    ImageToWorld(segmentation, m);
    if (!vtkRPSegmentationNode::IsLabelScalarType(segmentation->GetImageData() ? segmentation->GetImageData()->GetScalarType() : VTK_FLOAT) ||
        !SetSampler(model.Labels, segmentation->GetImageData(), m, error)) {
      error = "the segmentation '" + segmentation->GetName() + "' has no integer labelmap";
      return false;
    }
    const bool anyTissue = std::any_of(segmentation->GetSegments().begin(), segmentation->GetSegments().end(),
                                       [](const rp::Segment& s) { return !s.TissueClass.empty(); });
    for (const std::string& reference : boneSegments)
      if (!segmentation->FindSegment(reference)) {
        error = "no segment '" + reference + "' in the segmentation '" + segmentation->GetName() + "'";
        return false;
      }
    for (const rp::Segment& s : segmentation->GetSegments()) {
      bool bone = anyTissue ? IsBoneTissue(materials, s.TissueClass) : true;
      if (!boneSegments.empty())
        bone = std::any_of(boneSegments.begin(), boneSegments.end(),
                           [&](const std::string& r) { return segmentation->FindSegment(r) == &s; });
      model.Segments.push_back({s.LabelValue, s.Name, s.TissueClass, bone});
    }
    rule = !boneSegments.empty() ? "the segments named as bone"
           : anyTissue           ? "segments whose tissue class is a bone of materials.json"
                                 : "every segment (the segmentation names no tissue classes)";
  }
  model.Prepare();
  this->CTImage = ct ? ct->GetImageData() : nullptr;
  this->LabelImage = segmentation ? segmentation->GetImageData() : nullptr;
  this->Model = std::move(model);
  this->Rule = rule;
  return true;
}

}  // namespace rp
