// DICOM as a DataReader (rpDataLoader.h): a folder (searched recursively), a DICOMDIR or one
// DICOM file becomes one scalar volume node, the series chosen by ReadOptions::Series when there
// are several (`--series`, as `roboplan dicom` lists them). So every caller of rp::LoadPath
// (`mesh`, the viewer, `roboplan <folder>`) reads DICOM the way `convert` does.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "rpDataLoader.h"
#include "rpDicomSeries.h"
#include "rpImageVolume.h"
#include "rpImagingReaders.h"
#include "vtkRPScalarVolumeNode.h"

namespace rp {
namespace {

// A DICOM Part 10 file: a 128-byte preamble, then "DICM".
bool HasDicomMagic(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char header[132] = {};
  if (!file.read(header, sizeof header)) return false;
  return std::equal(header + 128, header + 132, "DICM");
}

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
    ImageVolume volume;
    DicomReadOptions dicom;
    dicom.ResampleIrregularSpacing = options.ResampleIrregularSpacing;
    if (!ReadDicomVolume(path, volume, result.Error, options.Series, dicom, &result.Warnings, options.Progress))
      return false;
    auto node = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
    node->SetName(volume.Description.empty() ? std::filesystem::path(path).filename().string() : volume.Description);
    CopyToNode(volume, node);  // window/level from the series, else from the scalar range
    result.Details["modality"] = volume.Modality;
    result.Details["description"] = volume.Description;
    result.Nodes.push_back(node);
    return true;
  }
};
const bool registeredAtLoad = RegisterImagingReaders();

}  // namespace

bool RegisterImagingReaders() {
  static const bool registered = RegisterDataReader(std::make_shared<DicomReader>());
  return registered;
}

}  // namespace rp
