#pragma once
// DICOM Segmentation objects (SEG, PS3.3 A.51) in and out of a segmentation node, with DCMTK's
// dcmseg (the library dcmqi, 3D Slicer's DICOM SEG converter, is built on).
//
// Read: binary (1-bit) and fractional (8-bit, thresholded at half the Maximum Fractional Value,
// with a warning) frames, each placed by its Plane Position; segments with their labels and
// colours (Recommended Display CIELab Value → sRGB). The labelmap has one label per segment
// (label value = Segment Number). With a referenced series the labelmap is on that series' grid
// and every frame is checked to lie on one of its slices (same orientation, pixel spacing,
// frame of reference); without one, on the grid the frames span. A voxel in two segments (a
// labelmap holds one) goes to the higher segment number, with a warning naming the pair.
//
// Write: a binary SEG of every segment, on the grid of a referenced series (the segmentation's
// grid must be that series' grid): patient, study and frame of reference taken from the series,
// a new series and instance UID, a Referenced Series Sequence listing every image, per frame its
// position, dimension indices (segment, position) and a Derivation Image naming its source
// image; segment codes as dcmqi writes them for generic segments (Tissue), or anatomic codes
// (SNOMED CT) for the knee's bones.
#include <string>
#include <vector>

class vtkRPSegmentationNode;

namespace rp {

struct DicomReferenceSeries;

/// Reads the SEG file `path` (or the only SEG in folder `path`) into `node`. `referencePath`
/// (optional): the referenced image series (folder), whose grid the labelmap takes.
bool ReadDicomSegmentation(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                           const std::string& referencePath = "", std::vector<std::string>* warnings = nullptr);

/// The same with the referenced series already read (rpDicomReferenceSeries.h): a study read
/// whole reads each series once, for its volume and the segmentations on it.
bool ReadDicomSegmentation(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                           const DicomReferenceSeries& reference, std::vector<std::string>* warnings = nullptr);

/// The tissue class a segment name gives where it names what the SEG writer codes (the knee's
/// bones, "bone": "Left Tibia" → "bone"); "" otherwise (rpDicomSegmentCodes.cxx: no DCMTK).
std::string KnownTissueClass(const std::string& segmentName);

struct DicomSegmentationWriteOptions {
  std::string SeriesDescription = "RoboPlan segmentation";
  std::string SeriesNumber = "300";
  std::string ContentLabel = "SEGMENTATION";
};

/// Writes `node` as a binary SEG file referencing the image series in `referencePath`.
bool WriteDicomSegmentation(vtkRPSegmentationNode* node, const std::string& referencePath,
                            const std::string& outputFile, std::string& error,
                            const DicomSegmentationWriteOptions& options = {});

}  // namespace rp
