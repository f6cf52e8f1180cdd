// The entry points of libRoboPlanDicomObjects.so: DICOM SEG (rpDicomSegmentation.cxx, dcmseg)
// and RTSTRUCT (rpDicomRtStruct.cxx, dcmrt), loaded on first use by RoboPlanImaging
// (rpDicomObjectsLoader.cxx). The library is built with hidden visibility: its own
// rp::ReadDicomSegmentation... bind inside it, not to the forwarding ones of RoboPlanImaging.
#include "rpDicomReferenceSeries.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"

#define RP_DICOM_OBJECTS_ENTRY extern "C" __attribute__((visibility("default")))

RP_DICOM_OBJECTS_ENTRY bool roboplan_read_dicom_segmentation(const std::string& path, vtkRPSegmentationNode* node,
                                                             std::string& error, const std::string& referencePath,
                                                             std::vector<std::string>* warnings) {
  return rp::ReadDicomSegmentation(path, node, error, referencePath, warnings);
}

RP_DICOM_OBJECTS_ENTRY bool roboplan_write_dicom_segmentation(vtkRPSegmentationNode* node,
                                                              const std::string& referencePath,
                                                              const std::string& outputFile, std::string& error,
                                                              const rp::DicomSegmentationWriteOptions& options) {
  return rp::WriteDicomSegmentation(node, referencePath, outputFile, error, options);
}

RP_DICOM_OBJECTS_ENTRY bool roboplan_read_dicom_rtstruct(const std::string& path, vtkRPSegmentationNode* node,
                                                         std::string& error, const std::string& referencePath,
                                                         std::vector<std::string>* warnings) {
  return rp::ReadDicomRtStruct(path, node, error, referencePath, warnings);
}

RP_DICOM_OBJECTS_ENTRY bool roboplan_read_dicom_segmentation_on(const std::string& file, vtkRPSegmentationNode* node,
                                                                std::string& error,
                                                                const rp::DicomReferenceSeries& reference,
                                                                std::vector<std::string>* warnings) {
  return rp::ReadDicomSegmentation(file, node, error, reference, warnings);
}

RP_DICOM_OBJECTS_ENTRY bool roboplan_read_dicom_rtstruct_on(const std::string& file, vtkRPSegmentationNode* node,
                                                            std::string& error, const rp::DicomReferenceSeries& reference,
                                                            std::vector<std::string>* warnings) {
  return rp::ReadDicomRtStruct(file, node, error, reference, warnings);
}
