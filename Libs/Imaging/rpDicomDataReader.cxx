// DICOM as a DataReader (rpDataLoader.h): a folder (searched recursively), a DICOMDIR or one
// DICOM file is read whole (rpDicomStudy.h): each image series a scalar volume node, each SEG
// and RTSTRUCT a segmentation node that references (vtkRPSegmentationNode::
// ReferenceImageGeometryRole) the volume it lies on, so the views show that volume under it.
// ReadOptions::Series (`--series`, as `roboplan dicom` lists the IDs) reads one object only. So
// every caller of rp::LoadPath (`mesh`, the viewer, `roboplan <folder>`) reads DICOM one way.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "rpDataLoader.h"
#include "rpDicomStudy.h"
#include "rpImageVolume.h"
#include "rpImagingReaders.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

// A DICOM Part 10 file: a 128-byte preamble, then "DICM".
bool HasDicomMagic(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char header[132] = {};
  if (!file.read(header, sizeof header)) return false;
  return std::equal(header + 128, header + 132, "DICM");
}

// The study's objects as nodes (not yet in a scene). Several nodes get IDs as the scene would
// give them (class name and number), so that a segmentation can reference its volume; LoadPath
// imports them together (an ID the scene has already is remapped, references following).
void AddStudyNodes(const std::string& path, DicomStudy& study, LoadResult& result) {
  const bool several = study.Volumes.size() + study.Segmentations.size() > 1;
  nlohmann::json objects = nlohmann::json::array();
  std::vector<vtkRPScalarVolumeNode*> volumes;
  for (DicomStudyVolume& read : study.Volumes) {
    auto node = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
    const ImageVolume& volume = read.Volume;
    node->SetName(volume.Description.empty() ? std::filesystem::path(path).filename().string() : volume.Description);
    CopyToNode(volume, node);  // window/level from the series, else from the scalar range
    if (several) node->SetIDInternal(node->GetClassName() + std::to_string(volumes.size() + 1));
    volumes.push_back(node);
    result.Nodes.push_back(node);
    objects.push_back({{"kind", "volume"}, {"id", read.Series.StackID}, {"modality", volume.Modality},
                       {"description", volume.Description}});
  }
  for (DicomStudySegmentation& read : study.Segmentations) {
    vtkRPSegmentationNode* node = read.Node;
    nlohmann::json object = {{"kind", read.Object.Kind}, {"id", read.Object.SeriesInstanceUID},
                             {"description", node->GetName()}, {"segments", node->GetNumberOfSegments()}};
    if (several) node->SetIDInternal(node->GetClassName() + std::to_string(objects.size() - volumes.size() + 1));
    if (read.ReferencedVolume >= 0) {
      const DicomStudyVolume& on = study.Volumes[static_cast<size_t>(read.ReferencedVolume)];
      node->SetNodeReferenceID(vtkRPSegmentationNode::ReferenceImageGeometryRole(),
                               volumes[static_cast<size_t>(read.ReferencedVolume)]->GetID());
      object["on"] = on.Series.StackID;
    }
    result.Nodes.push_back(read.Node);
    objects.push_back(object);
  }
  result.Details["objects"] = objects;
  if (!study.Volumes.empty()) {  // the first volume's, as for a single series
    result.Details["modality"] = study.Volumes.front().Volume.Modality;
    result.Details["description"] = study.Volumes.front().Volume.Description;
  }
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
    DicomStudyOptions study;
    study.Series = options.Series;
    study.Dicom.ResampleIrregularSpacing = options.ResampleIrregularSpacing;
    DicomStudy read;
    if (!ReadDicomStudy(path, read, result.Error, study, options.Progress)) return false;
    result.Warnings.insert(result.Warnings.end(), read.Warnings.begin(), read.Warnings.end());
    AddStudyNodes(path, read, result);
    return true;
  }
};
// The one DicomReader: registered, and what GetDicomDataReader names.
const std::shared_ptr<DataReader>& TheDicomReader() {
  static const std::shared_ptr<DataReader> reader = std::make_shared<DicomReader>();
  return reader;
}

}  // namespace

const DataReader* GetDicomDataReader() { return TheDicomReader().get(); }

bool RegisterImagingReaders() {
  static const bool registered = RegisterDataReader(TheDicomReader()) && RegisterDicomSegmentationReader();
  return registered;
}

}  // namespace rp
