// The entries of libRoboPlanDicom.so that code without the DICOM library resolves on its first
// DICOM read or write (names and types: rpDicomEntries.h): the loader's DICOM reads as nodes, the
// volume read and write of rpVolumeFiles.h, a folder's scan, DICOM SEG / RTSTRUCT in and out.
#include "rpDicomEntries.h"

#include <filesystem>
#include <type_traits>

#include "rpDataLoader.h"
#include "rpDicomReferenceSeries.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "rpDicomSeries.h"
#include "rpDicomStudy.h"
#include "rpDicomWriter.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

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

}  // namespace
}  // namespace rp

RP_DICOM_ENTRY bool roboplan_dicom_read_study(const std::string& path, const rp::ReadOptions& options,
                                              rp::LoadResult& result) {
  rp::DicomStudyOptions study;
  study.Series = options.Series;
  study.Dicom.ResampleIrregularSpacing = options.ResampleIrregularSpacing;
  rp::DicomStudy read;
  if (!rp::ReadDicomStudy(path, read, result.Error, study, options.Progress)) return false;
  result.Warnings.insert(result.Warnings.end(), read.Warnings.begin(), read.Warnings.end());
  rp::AddStudyNodes(path, read, result);
  return true;
}

RP_DICOM_ENTRY int roboplan_dicom_object_kind(const std::string& path, std::string* object, std::string* error) {
  return rp::DicomSegmentationObjectKind(path, object, error);
}

RP_DICOM_ENTRY bool roboplan_dicom_read_object(const std::string& path, rp::LoadResult& result) {
  std::string file;
  const int kind = rp::DicomSegmentationObjectKind(path, &file, &result.Error);
  if (kind <= 0) {
    if (kind == 0) result.Error = path + " holds no DICOM SEG or RTSTRUCT";
    return false;
  }
  auto node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  const bool ok = kind == 1 ? rp::ReadDicomSegmentation(file, node, result.Error, "", &result.Warnings)
                            : rp::ReadDicomRtStruct(file, node, result.Error, "", &result.Warnings);
  if (!ok) return false;
  if (node->GetName().empty()) node->SetName(std::filesystem::path(file).stem().string());
  result.Details["object"] = kind == 1 ? "SEG" : "RTSTRUCT";
  result.Details["segments"] = node->GetNumberOfSegments();
  result.Nodes.push_back(node);
  return true;
}

RP_DICOM_ENTRY bool roboplan_dicom_read_volume(const std::string& path, rp::ImageVolume& volume, std::string& error,
                                               const std::string& seriesID, const rp::DicomReadOptions& options,
                                               std::vector<std::string>* warnings,
                                               const rp::ProgressCallback& progress) {
  return rp::ReadDicomVolume(path, volume, error, seriesID, options, warnings, progress);
}

RP_DICOM_ENTRY bool roboplan_dicom_write_series(const rp::ImageVolume& volume, const std::string& folder,
                                                const rp::DicomWriteOptions& options, std::string& error,
                                                rp::DicomWriteResult* result, const rp::ProgressCallback& progress) {
  return rp::WriteDicomSeries(volume, folder, options, error, result, progress);
}

RP_DICOM_ENTRY bool roboplan_dicom_scan(const std::string& path, rp::DicomScanResult& result, std::string& error,
                                        const rp::ProgressCallback& progress) {
  return rp::ScanDicom(path, result, error, progress);
}

RP_DICOM_ENTRY bool roboplan_dicom_read_segmentation(const std::string& path, vtkRPSegmentationNode* node,
                                                     std::string& error, const std::string& referencePath,
                                                     std::vector<std::string>* warnings) {
  return rp::ReadDicomSegmentation(path, node, error, referencePath, warnings);
}

RP_DICOM_ENTRY bool roboplan_dicom_read_rtstruct(const std::string& path, vtkRPSegmentationNode* node,
                                                 std::string& error, const std::string& referencePath,
                                                 std::vector<std::string>* warnings) {
  return rp::ReadDicomRtStruct(path, node, error, referencePath, warnings);
}

RP_DICOM_ENTRY bool roboplan_dicom_write_segmentation(vtkRPSegmentationNode* node, const std::string& referencePath,
                                                      const std::string& outputFile, std::string& error,
                                                      const rp::DicomSegmentationWriteOptions& options) {
  return rp::WriteDicomSegmentation(node, referencePath, outputFile, error, options);
}

// The entries' types are the header's (a compile error here when one side changes).
static_assert(std::is_same_v<decltype(&roboplan_dicom_read_study), rp::dicom::ReadStudyFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_object_kind), rp::dicom::ObjectKindFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_read_object), rp::dicom::ReadObjectFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_read_volume), rp::dicom::ReadVolumeFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_write_series), rp::dicom::WriteSeriesFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_scan), rp::dicom::ScanFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_read_segmentation), rp::dicom::ReadSegmentationFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_read_rtstruct), rp::dicom::ReadSegmentationFunction>);
static_assert(std::is_same_v<decltype(&roboplan_dicom_write_segmentation), rp::dicom::WriteSegmentationFunction>);
