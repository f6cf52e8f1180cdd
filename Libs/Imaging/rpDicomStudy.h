#pragma once
// A DICOM folder (or DICOMDIR) read whole, as 3D Slicer's DICOM browser loads a study: every
// image series (stack) as a volume, every SEG and RTSTRUCT as a segmentation on the grid of the
// image series it references (read once, for its volume and for the segmentations on it),
// whatever the order of the files. One object alone when `Series` names it.
//
// Which series a segmentation lies on: the one it names (a SEG's Referenced Series Sequence, an
// RTSTRUCT's RT Referenced Series), else the only series read in its Frame of Reference, else
// (an RTSTRUCT, as ReadDicomRtStruct does) the only series read. A SEG whose series is not
// there, or whose frames do not lie on that series' slices, keeps the grid its frames span,
// with a warning; an RTSTRUCT without its series cannot be rasterized and is left out, with a
// warning. A series that cannot be read (several stacks under one UID, irregular spacing,
// corrupt files...) is left out with a warning naming why when anything else loads, and is the
// error when nothing does.
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpDicomSeries.h"
#include "rpImageVolume.h"
#include "rpProgress.h"

class vtkRPSegmentationNode;

namespace rp {

struct DicomStudyVolume {
  DicomSeriesInfo Series;
  ImageVolume Volume;
};

struct DicomStudySegmentation {
  DicomSegmentationObjectInfo Object;
  vtkSmartPointer<vtkRPSegmentationNode> Node;
  int ReferencedVolume = -1;  // index in DicomStudy::Volumes of the series it lies on; -1: none read
};

struct DicomStudy {
  std::vector<DicomStudyVolume> Volumes;
  std::vector<DicomStudySegmentation> Segmentations;
  std::vector<std::string> Warnings;  // objects left out and why, and the readers' notes
};

struct DicomStudyOptions {
  /// One object only: an image stack's ID (as `roboplan dicom` lists it, a SeriesInstanceUID or
  /// "<SeriesInstanceUID>#<n>"), or a SEG's or RTSTRUCT's SeriesInstanceUID. "": everything.
  std::string Series;
  DicomReadOptions Dicom;
};

/// Reads what `path` (a folder, a DICOMDIR or a DICOM file) holds. False (and `error` naming the
/// problem) when nothing could be read; `study` is only assigned on success.
bool ReadDicomStudy(const std::string& path, DicomStudy& study, std::string& error,
                    const DicomStudyOptions& options = {}, const ProgressCallback& progress = nullptr);

}  // namespace rp
