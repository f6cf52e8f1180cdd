#pragma once
// Segmentations as 3D Slicer's .seg.nrrd: a labelmap NRRD with the keys Slicer writes and reads
// (Segment<N>_ID, _Name, _Color, _LabelValue, _Layer, _Extent, _Tags, ...,
// Segmentation_MasterRepresentation, Segmentation_ConversionParameters, ...). The tissue class
// travels in the segment's tags ("RoboPlan.TissueClass:<class>"), as does a structure at risk's
// protection ("RoboPlan.Protected:true|RoboPlan.SafetyMarginMm:<mm>", rpProtection.h).
#include <string>

class vtkRPSegmentationNode;

namespace rp {

bool WriteSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error);
bool ReadSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error);
/// A .seg.nrrd, or any labelmap volume file: then one segment per label value found (ID the
/// value, name "Label <value>", no tissue class; at most 255). A path the loader reads as
/// something else (a model, a scene, DICOM) is refused with an error naming what it is.
bool ReadSegmentationOrLabelmap(const std::string& path, vtkRPSegmentationNode* node, std::string& error);

}  // namespace rp
