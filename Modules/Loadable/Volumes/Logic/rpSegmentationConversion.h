#pragma once
// Segmentation conversions (vtkRPVolumesLogic::ConvertSegmentation, `roboplan convert`):
//  - into a .seg.nrrd: a DICOM SEG or RTSTRUCT (with a reference series: on that series' grid),
//    the segmentation a DICOM folder holds (read whole by the one loader, rp::LoadPath: a SEG on
//    the series it references; `Series` picks one of several), another .seg.nrrd, or a labelmap
//    volume (one segment per label value, named and coloured by a label table: rpLabelmapInput.h);
//  - from a .seg.nrrd into a DICOM SEG on the grid of the reference series.
#include <string>
#include <vector>

namespace rp {

struct SegmentationConversionRequest {
  std::string In, Out;
  std::string Series;     // DICOM input: the object to read when the folder holds several
  std::string Reference;  // the DICOM image series a SEG or RTSTRUCT lies on (needed to write a SEG)
  std::string InputKind = "auto";  // a volume input: "auto", "labelmap" or "intensity"
  std::string Labels;     // label names and colours for a labelmap input (a table file)
  bool ResampleIrregularSpacing = false;
};

struct SegmentationConversion {
  bool Applies = false;  // In -> Out is a segmentation conversion (else a volume or scene one)
  int FailureCode = 0;   // 0: written; 2: the request does not make sense; 1: the work failed
  std::string Error;     // when FailureCode != 0: names the file and the problem
  std::string OutputFormat;  // "segmentation file" or "DICOM SEG"
  int Segments = 0;
  std::vector<std::string> SegmentNames;  // into a segmentation file
  std::string InputKind;                  // into a segmentation file: "segmentation" or "labelmap"
  std::string InputKindReason;            // a labelmap's: why its values were taken as labels
  std::vector<std::string> Warnings;
};

/// Runs the conversion when In -> Out is one of the above (Applies); nothing is done otherwise.
SegmentationConversion ConvertSegmentation(const SegmentationConversionRequest& request);

}  // namespace rp
