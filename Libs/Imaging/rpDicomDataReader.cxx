// DICOM as a DataReader (rpDataLoader.h): a folder (searched recursively), a DICOMDIR or one
// DICOM file is read whole (rpDicomStudy.h): each image series a scalar volume node, each SEG
// and RTSTRUCT a segmentation node that references (vtkRPSegmentationNode::
// ReferenceImageGeometryRole) the volume it lies on, so the views show that volume under it.
// ReadOptions::Series (`--series`, as `roboplan dicom` lists the IDs) reads one object only. So
// every caller of rp::LoadPath (`mesh`, the viewer, `roboplan <folder>`) reads DICOM one way.
// Telling DICOM needs no DCMTK; reading it is libRoboPlanDicom.so's (rpDicomEntries.h), loaded then.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "rpDataLoader.h"
#include "rpDicomEntries.h"
#include "rpDicomMagic.h"
#include "rpImagingReaders.h"
#include "rpSiblingLibrary.h"

namespace rp {
namespace {

class DicomReader : public DataReader {
 public:
  std::string Description() const override { return "DICOM"; }
  bool CanRead(const std::string& path) const override {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) return true;
    if (!fs::is_regular_file(path, ec)) return false;
    std::string name = fs::path(path).filename().string();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::toupper(c); });
    return name == "DICOMDIR" || HasExtension(path, ".dcm") || HasDicomMagic(path);
  }
  bool Read(const std::string& path, const ReadOptions& options, vtkRPScene*, LoadResult& result) const override {
    const auto read = dicom::Entry<dicom::ReadStudyFunction>(dicom::ReadStudyEntry, path, result.Error);
    return read && read(path, options, result);
  }
};
// The one DicomReader: registered, and what GetDicomDataReader names.
const std::shared_ptr<DataReader>& TheDicomReader() {
  static const std::shared_ptr<DataReader> reader = std::make_shared<DicomReader>();
  return reader;
}

}  // namespace

void* dicom::EntrySymbol(const char* symbol, const std::string& path, std::string& error) {
  std::string why;
  void* entry = SiblingLibrarySymbol(reinterpret_cast<const void*>(&dicom::EntrySymbol), dicom::Library, symbol, why);
  if (!entry) error = path + ": DICOM is not available: " + why;
  return entry;
}

const DataReader* GetDicomDataReader() { return TheDicomReader().get(); }

bool RegisterImagingReaders() {
  static const bool registered = RegisterDataReader(TheDicomReader()) && RegisterDicomSegmentationReader();
  return registered;
}

}  // namespace rp
