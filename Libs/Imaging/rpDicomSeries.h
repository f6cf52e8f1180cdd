#pragma once
// DICOM image series in: DCMTK parses, sorts and diagnoses; the pixels of every transfer syntax
// a PACS sends are decoded by DCMTK, or by GDCM for JPEG 2000 (rpDicomTransferSyntax.h lists them).
//
// Scan: a folder (recursively) or a DICOMDIR; files are grouped by SeriesInstanceUID, and a
// series that holds several stacks (a three-plane localizer, different orientations or image
// sizes under one UID) is split into its stacks, each listed and loadable on its own under the
// ID "<SeriesInstanceUID>#<n>". A multi-frame file (Enhanced CT/MR: one file, many frames, a
// position per frame in its functional groups) contributes one slice per frame.
// Read: slices sorted by their position along the slice normal (ImagePositionPatient ·
// (row × column of ImageOrientationPatient)), never by file name or InstanceNumber; slice
// spacing from the positions; oblique stacks keep their exact direction cosines;
// RescaleSlope/Intercept applied (CT in HU); window kept. The result is in RAS (rpLPSRAS.h).
// The memory a series needs is checked before any pixel is decoded.
//
// Policy for irregular series (documented, tested):
//  - a missing slice or uneven spacing is REFUSED by default with a message that names the
//    two positions (and files) around the gap; with `ResampleIrregularSpacing` the series is
//    loaded with its true geometry by linear interpolation onto a regular grid whose spacing
//    is the smallest gap, and a warning says so;
//  - gantry tilt, duplicate positions (echoes, time points), multi-frame images whose file
//    does not give the frames' geometry, colour and palette-colour images are refused with a
//    message naming the problem (Libs/Imaging/README.md says why);
//  - pixel values: RescaleSlope/Intercept, an RT Dose's DoseGridScaling or a Modality LUT
//    Sequence applied; 8/16/32-bit integer, Float and Double Float Pixel Data read;
//  - legacy multi-frame files (one position and orientation, Spacing Between Slices; RT Dose's
//    Grid Frame Offset Vector) contribute one slice per frame;
//  - an invalid PixelSpacing (0\0, negative, NaN) is read as 1 mm with a warning, as a missing one;
//  - a series of several stacks read without choosing one is refused, naming the stacks;
//  - non-DICOM files are skipped and counted; truncated or corrupt files are named.
#include <string>
#include <vector>

#include "rpImageVolume.h"
#include "rpProgress.h"

namespace rp {

/// One loadable stack: a whole series, or one stack of a series that holds several.
struct DicomSeriesInfo {
  /// What to pass to ReadDicomVolume / `--series`: the SeriesInstanceUID, or
  /// "<SeriesInstanceUID>#<StackIndex>" when the series holds several stacks.
  std::string StackID;
  int StackIndex = 1;  // 1-based
  int StackCount = 1;  // stacks under this SeriesInstanceUID
  std::string SeriesInstanceUID;
  std::string StudyInstanceUID;
  std::string FrameOfReferenceUID;
  std::string Modality;
  std::string SeriesDescription;
  std::string PatientName;
  std::string SeriesNumber;
  std::string TransferSyntaxUID;  // of the first file
  std::vector<std::string> Files;  // as found (not sorted geometrically)
  int Slices = 0;                  // images in the stack (a multi-frame file counts its frames)
  int Columns = 0;
  int Rows = 0;
  double Orientation[6] = {1, 0, 0, 0, 1, 0};  // ImageOrientationPatient (LPS) of the stack
  std::string OrientationName;                 // "axial", "oblique coronal (12.0°)", ...
  double PixelSpacing[2] = {0, 0};  // row spacing (between rows), column spacing (between columns)
  double SliceSpacing = 0.0;        // median gap between slice positions (0 if unknown)
  /// Files of this series that failed to parse ("path: reason"): the series is refused.
  std::vector<std::string> CorruptFiles;
  /// Human-readable reason the series cannot be read ("" if it looks loadable).
  std::string Problem;
  /// What the reader will assume or ignore when reading it (an invalid PixelSpacing read as
  /// 1 mm, frames spaced by their SliceThickness...): shown by `roboplan dicom`.
  std::vector<std::string> Warnings;
};

/// A DICOM Segmentation (SEG) or RT Structure Set (RTSTRUCT) object found by a scan: what it
/// is and the image series it segments (its Referenced Series Sequence, or an RTSTRUCT's
/// Referenced Frame of Reference > RT Referenced Study > RT Referenced Series).
struct DicomSegmentationObjectInfo {
  std::string File;
  std::string Kind;  // "SEG" or "RTSTRUCT"
  std::string SeriesInstanceUID, StudyInstanceUID, FrameOfReferenceUID;
  std::string SeriesDescription;  // an RTSTRUCT's Structure Set Label when it has no description
  std::string SeriesNumber;
  std::string TransferSyntaxUID;
  std::string ReferencedSeriesUID;    // "" when the object names none
  std::vector<std::string> Segments;  // segment labels (SEG) or ROI names (RTSTRUCT), in order
};

struct DicomScanResult {
  std::vector<DicomSeriesInfo> Series;
  std::vector<DicomSegmentationObjectInfo> Segmentations;  // SEG and RTSTRUCT objects
  int FilesExamined = 0;
  int NonDicomFiles = 0;       // skipped: not DICOM at all
  int NonImageDicomFiles = 0;  // skipped: DICOM without pixel data (DICOMDIR, SR, ...), SEG and RTSTRUCT aside
  std::vector<std::string> CorruptFiles;  // "path: reason" for DICOM files that failed to parse
};

/// Scans a folder recursively, or a DICOMDIR file (its referenced images): image series stack by
/// stack, and SEG and RTSTRUCT objects. Returns false only when `path` cannot be read at all;
/// skipped files are counted in the result.
bool ScanDicom(const std::string& path, DicomScanResult& result, std::string& error,
               const ProgressCallback& progress = nullptr);

struct DicomReadOptions {
  bool ResampleIrregularSpacing = false;  // see the policy above
  double SpacingTolerance = 0.01;         // relative tolerance on gaps between slices
};

/// "axial", "sagittal", "coronal", or "oblique sagittal (12.0°)" beyond 0.5° from the nearest
/// of those planes, from an ImageOrientationPatient.
std::string OrientationName(const double imageOrientationPatient[6]);

/// Reads one series into a volume (short when the rescaled values are integers that fit,
/// float otherwise). `warnings` (optional) receives non-fatal notes. `volume` is only
/// assigned on success.
bool ReadDicomSeries(const DicomSeriesInfo& series, ImageVolume& volume, std::string& error,
                     const DicomReadOptions& options = {}, std::vector<std::string>* warnings = nullptr,
                     const ProgressCallback& progress = nullptr);

/// The stack of `scan` that `seriesID` names (a StackID, or a SeriesInstanceUID that holds one
/// stack), or its only stack when `seriesID` is empty; nullptr, with `error` naming the choices
/// (or that there is none), otherwise. `path` is the scanned path, for messages.
const DicomSeriesInfo* ChooseDicomStack(const DicomScanResult& scan, const std::string& path,
                                        const std::string& seriesID, std::string& error);

/// Convenience: scans `path` and reads the only stack, or the one `seriesID` names (a StackID,
/// or a SeriesInstanceUID that holds one stack).
bool ReadDicomVolume(const std::string& path, ImageVolume& volume, std::string& error,
                     const std::string& seriesID = "", const DicomReadOptions& options = {},
                     std::vector<std::string>* warnings = nullptr, const ProgressCallback& progress = nullptr);

}  // namespace rp
