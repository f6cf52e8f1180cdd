#pragma once
// The entries of libRoboPlanDicom.so (rpDicomEntries.cxx) that code which does not link the DICOM
// library reaches when it meets DICOM: the loader's DICOM and DICOM SEG / RTSTRUCT readers
// (rpDicomDataReader.cxx, rpDicomSegmentationDataReader.cxx), ReadVolume / WriteVolume
// (rpVolumeFiles.cxx), and the Volumes logic, the demo and the viewer (a folder's scan, DICOM SEG /
// RTSTRUCT conversion, a series written with its UIDs). Their names and types, in one place for
// both sides. None of those links the DICOM library (DCMTK, CharLS: 10 libraries and about a tenth
// of the symbol bindings of a command's start-up); it is loaded on the first DICOM read or write.
// Tests and benchmarks that call the DICOM API itself link RoboPlanDicom.
#include <string>
#include <vector>

#include "rpImageVolume.h"
#include "rpProgress.h"

#define RP_DICOM_ENTRY extern "C" __attribute__((visibility("default")))

class vtkRPSegmentationNode;

namespace rp {
struct DicomReadOptions;
struct DicomScanResult;
struct DicomSegmentationWriteOptions;
struct DicomWriteOptions;
struct DicomWriteResult;
struct LoadResult;
struct ReadOptions;
}  // namespace rp

namespace rp::dicom {

constexpr const char* Library = "libRoboPlanDicom.so";

/// roboplan_dicom_read_study: a folder, DICOMDIR or file read whole as the loader's nodes (each
/// image series a volume, each SEG / RTSTRUCT a segmentation on its volume; rpDicomStudy.h).
using ReadStudyFunction = bool (*)(const std::string& path, const ReadOptions& options, LoadResult& result);
constexpr const char* ReadStudyEntry = "roboplan_dicom_read_study";

/// roboplan_dicom_object_kind: rp::DicomSegmentationObjectKind (1 SEG, 2 RTSTRUCT, 0 other, -1 several).
using ObjectKindFunction = int (*)(const std::string& path, std::string* object, std::string* error);
constexpr const char* ObjectKindEntry = "roboplan_dicom_object_kind";

/// roboplan_dicom_read_object: a SEG or RTSTRUCT file alone as one segmentation node.
using ReadObjectFunction = bool (*)(const std::string& path, LoadResult& result);
constexpr const char* ReadObjectEntry = "roboplan_dicom_read_object";

/// roboplan_dicom_read_volume: rp::ReadDicomVolume (rpDicomSeries.h).
using ReadVolumeFunction = bool (*)(const std::string& path, ImageVolume& volume, std::string& error,
                                    const std::string& seriesID, const DicomReadOptions& options,
                                    std::vector<std::string>* warnings, const ProgressCallback& progress);
constexpr const char* ReadVolumeEntry = "roboplan_dicom_read_volume";

/// roboplan_dicom_write_series: rp::WriteDicomSeries (rpDicomWriter.h).
using WriteSeriesFunction = bool (*)(const ImageVolume& volume, const std::string& folder,
                                     const DicomWriteOptions& options, std::string& error, DicomWriteResult* result,
                                     const ProgressCallback& progress);
constexpr const char* WriteSeriesEntry = "roboplan_dicom_write_series";

/// roboplan_dicom_scan: rp::ScanDicom (rpDicomSeries.h), what `roboplan dicom` and the viewer's
/// DICOM browser list.
using ScanFunction = bool (*)(const std::string& path, DicomScanResult& result, std::string& error,
                              const ProgressCallback& progress);
constexpr const char* ScanEntry = "roboplan_dicom_scan";

/// roboplan_dicom_read_segmentation / roboplan_dicom_read_rtstruct: rp::ReadDicomSegmentation and
/// rp::ReadDicomRtStruct from a path, on the grid of the series `referencePath` ("": their own).
using ReadSegmentationFunction = bool (*)(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                                          const std::string& referencePath, std::vector<std::string>* warnings);
constexpr const char* ReadSegmentationEntry = "roboplan_dicom_read_segmentation";
constexpr const char* ReadRtStructEntry = "roboplan_dicom_read_rtstruct";

/// roboplan_dicom_write_segmentation: rp::WriteDicomSegmentation (rpDicomSegmentation.h).
using WriteSegmentationFunction = bool (*)(vtkRPSegmentationNode* node, const std::string& referencePath,
                                           const std::string& outputFile, std::string& error,
                                           const DicomSegmentationWriteOptions& options);
constexpr const char* WriteSegmentationEntry = "roboplan_dicom_write_segmentation";

/// The entry `symbol` of libRoboPlanDicom.so beside RoboPlanImaging, loaded on first use
/// (rpDicomDataReader.cxx). nullptr with `error` = "<path>: DICOM is not available: cannot load
/// <library file>: <why>".
void* EntrySymbol(const char* symbol, const std::string& path, std::string& error);

template <typename Function>
Function Entry(const char* symbol, const std::string& path, std::string& error) {
  return reinterpret_cast<Function>(EntrySymbol(symbol, path, error));
}

}  // namespace rp::dicom
