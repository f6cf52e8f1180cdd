#pragma once
// A volume out as a DICOM series (DCMTK): one CT Image Storage or MR Image Storage file per
// slice, valid UIDs, ImagePositionPatient / ImageOrientationPatient / PixelSpacing from the
// IJK-to-RAS matrix (RAS → LPS here, once) and a rescale so that reading the series back
// (rpDicomSeries) gives the same voxels and the same geometry.
//
// Exact for 8/16-bit integer volumes and for integer volumes whose range spans < 65536;
// float volumes are stored with a linear rescale (lossy, max error reported by the writer).
// The slice axis must be perpendicular to the rows and columns (no shear). When it points
// against row × column the slices are written in reverse order, so the read-back volume is
// the same image with k flipped (same voxels at the same RAS positions).
#include <string>

#include "rpImageVolume.h"
#include "rpProgress.h"

namespace rp {

struct DicomWriteOptions {
  std::string Modality = "CT";  // "CT" → CT Image Storage, "MR" → MR Image Storage
  std::string PatientName = "RoboPlan^Phantom";
  std::string PatientID = "RP0001";
  std::string StudyInstanceUID;  // generated when empty (give the same one to CT and MR)
  std::string FrameOfReferenceUID;  // generated when empty
  std::string SeriesDescription;
  int SeriesNumber = 1;
  std::string FilePrefix = "IM";  // files IM00001.dcm, IM00002.dcm, ...
};

struct DicomWriteResult {
  std::string SeriesInstanceUID;
  std::string StudyInstanceUID;
  int FilesWritten = 0;
  double MaxQuantizationError = 0.0;  // 0 for exactly representable volumes
};

/// Writes the series into `folder` (created if needed). Returns false with `error` naming the
/// problem (unsupported geometry, empty volume, write failure).
bool WriteDicomSeries(const ImageVolume& volume, const std::string& folder, const DicomWriteOptions& options,
                      std::string& error, DicomWriteResult* result = nullptr,
                      const ProgressCallback& progress = nullptr);

}  // namespace rp
