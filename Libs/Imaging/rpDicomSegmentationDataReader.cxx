// DICOM SEG and RTSTRUCT files as a DataReader (rpDataLoader.h): such a file alone becomes one
// segmentation node, so every caller of rp::LoadPath (`mesh`, the viewer, `roboplan <path>`)
// takes them wherever it takes a .seg.nrrd. It outranks the DICOM reader for such files
// (Priority 1); a folder holding them is the DICOM reader's (rpDicomDataReader.cxx: the study
// whole). The SEG keeps the grid its frames span; an RTSTRUCT is rasterized on the image series
// in its folder (rpDicomRtStruct.h). Only a file that may be DICOM (MaybeDicomFile) loads the
// DICOM library (rpDicomEntries.h) to be told apart.
#include <filesystem>

#include "rpDataLoader.h"
#include "rpDicomEntries.h"
#include "rpDicomMagic.h"
#include "rpImagingReaders.h"

namespace rp {
namespace {

class DicomSegmentationReader : public DataReader {
 public:
  std::string Description() const override { return "DICOM SEG / RTSTRUCT"; }
  bool CanRead(const std::string& path) const override {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec) || !MaybeDicomFile(path)) return false;
    std::string unused;
    const auto kind = dicom::Entry<dicom::ObjectKindFunction>(dicom::ObjectKindEntry, path, unused);
    return kind && kind(path, nullptr, nullptr) > 0;  // no DICOM library: the DICOM reader says so
  }
  int Priority() const override { return 1; }
  bool Read(const std::string& path, const ReadOptions&, vtkRPScene*, LoadResult& result) const override {
    const auto read = dicom::Entry<dicom::ReadObjectFunction>(dicom::ReadObjectEntry, path, result.Error);
    return read && read(path, result);
  }
};

}  // namespace

bool RegisterDicomSegmentationReader() {
  static const bool registered = RegisterDataReader(std::make_shared<DicomSegmentationReader>());
  return registered;
}

}  // namespace rp
