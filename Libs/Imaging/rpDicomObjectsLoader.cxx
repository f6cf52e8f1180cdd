// ReadDicomSegmentation (from a path or an already read series), WriteDicomSegmentation and
// ReadDicomRtStruct (rpDicomSegmentation.h, rpDicomRtStruct.h) forward to
// libRoboPlanDicomObjects.so beside this library, loaded on the first SEG or RTSTRUCT: DCMTK's
// dcmseg, dcmfg, dcmiod and dcmrt are about a quarter of the symbol bindings of every program that
// links RoboPlanDicom, and few read them.
// The library's entry points: rpDicomObjectsEntry.cxx.
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "rpSiblingLibrary.h"

namespace rp {

namespace {
template <typename Function>
Function DicomObjects(const char* symbol, std::string& error) {
  std::string loadError;
  const auto function = SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&DicomObjects<Function>),
                                                         "libRoboPlanDicomObjects.so", symbol, loadError);
  if (!function) error = "DICOM SEG and RTSTRUCT support is not available: " + loadError;
  return function;
}
}  // namespace

bool ReadDicomSegmentation(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                           const std::string& referencePath, std::vector<std::string>* warnings) {
  using Read = bool (*)(const std::string&, vtkRPSegmentationNode*, std::string&, const std::string&,
                        std::vector<std::string>*);
  const auto read = DicomObjects<Read>("roboplan_read_dicom_segmentation", error);
  return read && read(path, node, error, referencePath, warnings);
}

bool WriteDicomSegmentation(vtkRPSegmentationNode* node, const std::string& referencePath, const std::string& outputFile,
                            std::string& error, const DicomSegmentationWriteOptions& options) {
  using Write = bool (*)(vtkRPSegmentationNode*, const std::string&, const std::string&, std::string&,
                         const DicomSegmentationWriteOptions&);
  const auto write = DicomObjects<Write>("roboplan_write_dicom_segmentation", error);
  return write && write(node, referencePath, outputFile, error, options);
}

bool ReadDicomRtStruct(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                       const std::string& referencePath, std::vector<std::string>* warnings) {
  using Read = bool (*)(const std::string&, vtkRPSegmentationNode*, std::string&, const std::string&,
                        std::vector<std::string>*);
  const auto read = DicomObjects<Read>("roboplan_read_dicom_rtstruct", error);
  return read && read(path, node, error, referencePath, warnings);
}

bool ReadDicomSegmentation(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                           const DicomReferenceSeries& reference, std::vector<std::string>* warnings) {
  using Read = bool (*)(const std::string&, vtkRPSegmentationNode*, std::string&, const DicomReferenceSeries&,
                        std::vector<std::string>*);
  const auto read = DicomObjects<Read>("roboplan_read_dicom_segmentation_on", error);
  return read && read(file, node, error, reference, warnings);
}

bool ReadDicomRtStruct(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                       const DicomReferenceSeries& reference, std::vector<std::string>* warnings) {
  using Read = bool (*)(const std::string&, vtkRPSegmentationNode*, std::string&, const DicomReferenceSeries&,
                        std::vector<std::string>*);
  const auto read = DicomObjects<Read>("roboplan_read_dicom_rtstruct_on", error);
  return read && read(file, node, error, reference, warnings);
}

}  // namespace rp
