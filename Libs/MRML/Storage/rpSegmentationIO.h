#pragma once
// Segmentations as 3D Slicer's .seg.nrrd: a labelmap NRRD with the keys Slicer writes and reads
// (Segment<N>_ID, _Name, _Color, _LabelValue, _Layer, _Extent, _Tags, ...,
// Segmentation_MasterRepresentation, Segmentation_ConversionParameters, ...). The tissue class
// travels in the segment's tags ("RoboPlan.TissueClass:<class>").
#include <string>

class vtkRPSegmentationNode;

namespace rp {

bool WriteSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error);
bool ReadSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error);

}  // namespace rp
