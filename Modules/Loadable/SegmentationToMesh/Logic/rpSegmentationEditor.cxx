// What RoboPlanSegmentationToMeshLogic holds of rp::SegmentationEditor (rpSegmentationEditor.h):
// the presets, the labelmap set up on a volume's grid, and the forwarders to the edits' ITK side
// in libRoboPlanSegmentationItk.so beside this library (rpSegmentationItkEntries.h), loaded on the
// first edit that needs ITK.
#include "rpSegmentationEditor.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpSegmentationItkEntries.h"
#include "vtkRPImageNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

namespace segmentationitk {
bool HasImage(vtkRPImageNode* node) {
  return node && node->GetImageData() && node->GetImageData()->GetPointData()->GetScalars() &&
         node->GetImageData()->GetNumberOfPoints() > 0;
}
}  // namespace segmentationitk

const std::vector<ThresholdPreset>& ThresholdPresets() {
  static const std::vector<ThresholdPreset> presets = {
      {"bone", "bone", 226, 3071, {0.945, 0.839, 0.569}},
      {"cortical", "bone", 700, 3071, {1.0, 1.0, 0.9}},
      {"soft-tissue", "muscle", -100, 225, {0.8, 0.4, 0.35}},
      {"fat", "fat", -190, -30, {0.95, 0.85, 0.4}},
  };
  return presets;
}

const ThresholdPreset* FindThresholdPreset(const std::string& name) {
  for (const auto& p : ThresholdPresets())
    if (p.Name == name) return &p;
  return nullptr;
}

bool ParseMorphology(const std::string& text, Morphology& op) {
  if (text == "closing" || text == "close")
    op = Morphology::Closing;
  else if (text == "opening" || text == "open")
    op = Morphology::Opening;
  else if (text == "fill-holes" || text == "fillholes")
    op = Morphology::FillHoles;
  else if (text == "dilate")
    op = Morphology::Dilate;
  else if (text == "erode")
    op = Morphology::Erode;
  else
    return false;
  return true;
}

bool SegmentationEditor::InitializeFromVolume(vtkRPImageNode* volume,
                                              vtkRPSegmentationNode* segmentation,
                                              std::string& error) {
  if (!segmentationitk::HasImage(volume)) {
    error = "the volume has no image data";
    return false;
  }
  vtkNew<vtkImageData> labelmap;
  labelmap->SetDimensions(volume->GetImageData()->GetDimensions());
  labelmap->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  labelmap->GetPointData()->GetScalars()->Fill(0);
  const int previous = segmentation->StartModify();
  segmentation->SetImageData(labelmap);
  segmentation->SetIJKToRASMatrix(volume->GetIJKToRASMatrix());
  segmentation->RemoveAllSegments();
  segmentation->EndModify(previous);
  return true;
}

bool SegmentationEditor::Threshold(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation,
                                   const SegmentTarget& target, double lower, double upper,
                                   EditResult& result, std::string& error) {
  return segmentationitk::Call<segmentationitk::ThresholdFunction>(
      segmentationitk::ThresholdEntry, error, volume, segmentation, target, lower, upper, result,
      error);
}

bool SegmentationEditor::RegionGrow(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation,
                                    const SegmentTarget& target,
                                    const std::vector<std::array<double, 3>>& seedsRAS,
                                    double lower, double upper, EditResult& result,
                                    std::string& error) {
  return segmentationitk::Call<segmentationitk::RegionGrowFunction>(
      segmentationitk::RegionGrowEntry, error, volume, segmentation, target, seedsRAS, lower, upper,
      result, error);
}

bool SegmentationEditor::ConfidenceConnected(vtkRPImageNode* volume,
                                             vtkRPSegmentationNode* segmentation,
                                             const SegmentTarget& target,
                                             const std::vector<std::array<double, 3>>& seedsRAS,
                                             double multiplier, int iterations, int radius,
                                             EditResult& result, std::string& error) {
  return segmentationitk::Call<segmentationitk::ConfidenceConnectedFunction>(
      segmentationitk::ConfidenceConnectedEntry, error, volume, segmentation, target, seedsRAS,
      multiplier, iterations, radius, result, error);
}

bool SegmentationEditor::ApplyMorphology(vtkRPSegmentationNode* segmentation,
                                         const std::string& segmentID, Morphology op,
                                         double radiusMm, EditResult& result, std::string& error) {
  return segmentationitk::Call<segmentationitk::ApplyMorphologyFunction>(
      segmentationitk::ApplyMorphologyEntry, error, segmentation, segmentID, op, radiusMm, result,
      error);
}

bool SegmentationEditor::KeepLargestComponent(vtkRPSegmentationNode* segmentation,
                                              const std::string& segmentID, EditResult& result,
                                              std::string& error) {
  return segmentationitk::Call<segmentationitk::KeepLargestComponentFunction>(
      segmentationitk::KeepLargestComponentEntry, error, segmentation, segmentID, result, error);
}

bool SegmentationEditor::KeepComponentAtSeed(vtkRPSegmentationNode* segmentation,
                                             const std::string& segmentID,
                                             const std::array<double, 3>& seedRAS,
                                             EditResult& result, std::string& error) {
  return segmentationitk::Call<segmentationitk::KeepComponentAtSeedFunction>(
      segmentationitk::KeepComponentAtSeedEntry, error, segmentation, segmentID, seedRAS, result,
      error);
}

bool SegmentationEditor::SplitComponents(vtkRPSegmentationNode* segmentation,
                                         const std::string& segmentID, int maxSegments,
                                         long minVoxels, EditResult& result, std::string& error) {
  return segmentationitk::Call<segmentationitk::SplitComponentsFunction>(
      segmentationitk::SplitComponentsEntry, error, segmentation, segmentID, maxSegments, minVoxels,
      result, error);
}

}  // namespace rp
