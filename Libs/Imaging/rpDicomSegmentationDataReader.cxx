// DICOM SEG and RTSTRUCT files as a DataReader (rpDataLoader.h): such a file alone becomes one
// segmentation node, so every caller of rp::LoadPath (`mesh`, the viewer, `roboplan <path>`)
// takes them wherever it takes a .seg.nrrd. It outranks the DICOM reader for such files
// (Priority 1); a folder holding them is the DICOM reader's (rpDicomDataReader.cxx: the study
// whole). The SEG keeps the grid its frames span; an RTSTRUCT is rasterized on the image series
// in its folder (rpDicomRtStruct.h).
#include <filesystem>

#include "rpDataLoader.h"
#include "rpDicomReferenceSeries.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "rpImagingReaders.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

class DicomSegmentationReader : public DataReader {
 public:
  std::string Description() const override { return "DICOM SEG / RTSTRUCT"; }
  bool CanRead(const std::string& path) const override {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec) && DicomSegmentationObjectKind(path) > 0;
  }
  int Priority() const override { return 1; }
  bool Read(const std::string& path, const ReadOptions&, vtkRPScene*, LoadResult& result) const override {
    std::string file;
    const int kind = DicomSegmentationObjectKind(path, &file, &result.Error);
    if (kind <= 0) {
      if (kind == 0) result.Error = path + " holds no DICOM SEG or RTSTRUCT";
      return false;
    }
    auto node = vtkSmartPointer<vtkRPSegmentationNode>::New();
    const bool ok = kind == 1 ? ReadDicomSegmentation(file, node, result.Error, "", &result.Warnings)
                              : ReadDicomRtStruct(file, node, result.Error, "", &result.Warnings);
    if (!ok) return false;
    if (node->GetName().empty()) node->SetName(std::filesystem::path(file).stem().string());
    result.Details["object"] = kind == 1 ? "SEG" : "RTSTRUCT";
    result.Details["segments"] = node->GetNumberOfSegments();
    result.Nodes.push_back(node);
    return true;
  }
};

}  // namespace

bool RegisterDicomSegmentationReader() {
  static const bool registered = RegisterDataReader(std::make_shared<DicomSegmentationReader>());
  return registered;
}

}  // namespace rp
