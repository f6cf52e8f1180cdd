#pragma once
// The image series a DICOM segmentation (SEG) or structure set (RTSTRUCT) refers to: its grid,
// read exactly as ReadDicomVolume reads the series (so a SEG written here and a CT loaded from
// the same folder agree voxel for voxel), and, per slice, the UIDs a SEG's derivation images
// and Referenced Series Sequence name. Shared by rpDicomSegmentation and rpDicomRtStruct.
#include <string>
#include <vector>

#include "rpImageVolume.h"

namespace rp {

struct DicomSeriesInfo;

struct DicomReferenceSeries {
  ImageVolume Volume;  // voxels and IJK-to-RAS of the series
  std::string SeriesInstanceUID, StudyInstanceUID, FrameOfReferenceUID;
  std::string FirstFile;  // a file of the series (patient, study and frame of reference come from it)
  /// Per slice k of Volume: the image's SOP class and instance UIDs ("" when no single-frame
  /// image lies on that slice, e.g. a multi-frame series).
  std::vector<std::string> SOPClassUIDs, SOPInstanceUIDs;
};

/// Reads the only image series (or stack) under `path` (folder, DICOMDIR or file), or the one
/// `seriesUID` names when several are there. Segmentation objects in the folder are skipped.
bool ReadDicomReferenceSeries(const std::string& path, DicomReferenceSeries& reference, std::string& error,
                              const std::string& seriesUID = "");

/// A series already read (its scan entry and volume) as the reference of a SEG or RTSTRUCT:
/// grid and UIDs, without the per-slice SOP UIDs (only writing a SEG needs them). A study read
/// whole reads each series once for its volume and for the segmentations on it.
DicomReferenceSeries DicomReferenceFromVolume(const DicomSeriesInfo& series, const ImageVolume& volume);

/// 1 when `path` is a DICOM SEG, 2 an RTSTRUCT, 0 otherwise; `object` receives the file. A
/// folder is searched for such a file; -1 when it holds several (`error` names them).
int DicomSegmentationObjectKind(const std::string& path, std::string* object = nullptr, std::string* error = nullptr);

}  // namespace rp
