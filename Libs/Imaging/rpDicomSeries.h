#pragma once
// DICOM image series in (DCMTK directly: Debian's ITK has no ITKIODCMTK).
//
// Scan: a folder (recursively) or a DICOMDIR; files are grouped by SeriesInstanceUID.
// Read: slices sorted by their position along the slice normal (ImagePositionPatient ·
// (row × column of ImageOrientationPatient)), never by file name or InstanceNumber; slice
// spacing from the positions; RescaleSlope/Intercept applied (CT in HU); window kept;
// compressed syntaxes DCMTK decodes (JPEG baseline/extended/lossless, JPEG-LS, RLE).
// The result is in RAS: the LPS → RAS flip happens here, once.
//
// Policy for irregular series (documented, tested):
//  - a missing slice or uneven spacing is REFUSED by default with a message that names the
//    two positions (and files) around the gap; with `ResampleIrregularSpacing` the series is
//    loaded with its true geometry by linear interpolation onto a regular grid whose spacing
//    is the smallest gap, and a warning says so;
//  - mixed orientations, mixed image sizes, gantry tilt, duplicate positions, multi-frame and
//    colour images are refused with a message naming the problem (and a file);
//  - non-DICOM files are skipped and counted; truncated or corrupt files are named.
#include <string>
#include <vector>

#include "rpImageVolume.h"
#include "rpProgress.h"

namespace rp {

struct DicomSeriesInfo {
  std::string SeriesInstanceUID;
  std::string StudyInstanceUID;
  std::string Modality;
  std::string SeriesDescription;
  std::string PatientName;
  std::string SeriesNumber;
  std::string TransferSyntaxUID;  // of the first file
  std::vector<std::string> Files;  // as found (not sorted geometrically)
  int Columns = 0;
  int Rows = 0;
  double PixelSpacing[2] = {0, 0};  // row spacing (between rows), column spacing (between columns)
  double SliceSpacing = 0.0;        // median gap between slice positions (0 if unknown)
  /// Files of this series that failed to parse ("path: reason"): the series is refused.
  std::vector<std::string> CorruptFiles;
  /// Human-readable reason the series cannot be read ("" if it looks loadable).
  std::string Problem;
};

struct DicomScanResult {
  std::vector<DicomSeriesInfo> Series;
  int FilesExamined = 0;
  int NonDicomFiles = 0;       // skipped: not DICOM at all
  int NonImageDicomFiles = 0;  // skipped: DICOM without pixel data (DICOMDIR, SR, ...)
  std::vector<std::string> CorruptFiles;  // "path: reason" for DICOM files that failed to parse
};

/// Scans a folder recursively, or a DICOMDIR file (its referenced images). Returns false only
/// when `path` cannot be read at all; skipped files are counted in the result.
bool ScanDicom(const std::string& path, DicomScanResult& result, std::string& error,
               const ProgressCallback& progress = nullptr);

struct DicomReadOptions {
  bool ResampleIrregularSpacing = false;  // see the policy above
  double SpacingTolerance = 0.01;         // relative tolerance on gaps between slices
};

/// Reads one series into a volume (short when the rescaled values are integers that fit,
/// float otherwise). `warnings` (optional) receives non-fatal notes. `volume` is only
/// assigned on success.
bool ReadDicomSeries(const DicomSeriesInfo& series, ImageVolume& volume, std::string& error,
                     const DicomReadOptions& options = {}, std::vector<std::string>* warnings = nullptr,
                     const ProgressCallback& progress = nullptr);

/// Convenience: scans `path` and reads the only series (or the one with `seriesUID`).
bool ReadDicomVolume(const std::string& path, ImageVolume& volume, std::string& error,
                     const std::string& seriesUID = "", const DicomReadOptions& options = {},
                     std::vector<std::string>* warnings = nullptr, const ProgressCallback& progress = nullptr);

}  // namespace rp
