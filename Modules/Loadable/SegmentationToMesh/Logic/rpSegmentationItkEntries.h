#pragma once
// Internal to RoboPlanSegmentationToMeshLogic and libRoboPlanSegmentationItk.so: the entries
// through which rp::SegmentationEditor's edits (rpSegmentationEditor.cxx) and the bone masks'
// morphology and distance map (rpBoneMasks.cxx) reach their ITK side (rpSegmentationItk.cxx),
// loaded on the first such call. Each entry's name and type in one place for both sides; each
// type is the C++ function's own. ITK (ITKCommon, LabelMap, RegionGrowing, vnl_algo and through
// them vnl, v3p_netlib, itksys, double-conversion; v3p_netlib runs code when it loads) is then
// mapped only by a program that segments, not by every command of the modules that can
// (`mesh --help`, `demo --help`).
#include <string>
#include <utility>

#include "rpBoneMasks.h"
#include "rpSegmentationEditor.h"
#include "rpSiblingLibrary.h"

#define RP_SEGMENTATION_ITK_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::segmentationitk {

constexpr const char* Library = "libRoboPlanSegmentationItk.so";

using ThresholdFunction = decltype(&SegmentationEditor::Threshold);
constexpr const char* ThresholdEntry = "roboplan_segmentation_threshold";
using RegionGrowFunction = decltype(&SegmentationEditor::RegionGrow);
constexpr const char* RegionGrowEntry = "roboplan_segmentation_region_grow";
using ConfidenceConnectedFunction = decltype(&SegmentationEditor::ConfidenceConnected);
constexpr const char* ConfidenceConnectedEntry = "roboplan_segmentation_confidence_connected";
using ApplyMorphologyFunction = decltype(&SegmentationEditor::ApplyMorphology);
constexpr const char* ApplyMorphologyEntry = "roboplan_segmentation_apply_morphology";
using KeepLargestComponentFunction = decltype(&SegmentationEditor::KeepLargestComponent);
constexpr const char* KeepLargestComponentEntry = "roboplan_segmentation_keep_largest_component";
using KeepComponentAtSeedFunction = decltype(&SegmentationEditor::KeepComponentAtSeed);
constexpr const char* KeepComponentAtSeedEntry = "roboplan_segmentation_keep_component_at_seed";
using SplitComponentsFunction = decltype(&SegmentationEditor::SplitComponents);
constexpr const char* SplitComponentsEntry = "roboplan_segmentation_split_components";
using MaskMorphologyFunction = decltype(&bonesplit::MaskMorphology);
constexpr const char* MaskMorphologyEntry = "roboplan_bone_mask_morphology";
using DistanceInsideBoneFunction = decltype(&bonesplit::DistanceInsideBone);
constexpr const char* DistanceInsideBoneEntry = "roboplan_bone_distance_inside";

/// The node holds a non-empty image with scalars (in the logic; both sides ask it).
bool HasImage(vtkRPImageNode* node);

/// The logic's forwarders: `entry` (of type Function) called with `args`, the library loaded on
/// the first call; false with `error` naming the library's file and why when it cannot load.
template <typename Function, typename... Args>
bool Call(const char* entry, std::string& error, Args&&... args) {
  std::string why;
  const auto function = SiblingLibraryFunction<Function>(
      reinterpret_cast<const void*>(&SegmentationEditor::Threshold), Library, entry, why);
  if (!function) {
    error = "segmentation with ITK is not available: " + why;
    return false;
  }
  return function(std::forward<Args>(args)...);
}

}  // namespace rp::segmentationitk
