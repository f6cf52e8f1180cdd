#pragma once
// DICOM RT Structure Sets (RTSTRUCT, PS3.3 A.19) into a segmentation node, with DCMTK's dcmrt.
//
// Each ROI's CLOSED_PLANAR contours are rasterized onto the grid of the referenced image series
// (a voxel is inside when its centre is inside an odd number of the ROI's contours on its slice:
// nested contours make holes, as RT planning systems draw them); one labelmap segment per ROI,
// named by its ROI Name and coloured by its ROI Display Color. A contour that lies on no slice
// of the grid (outside it, or between two slices) is left out with a warning naming its ROI;
// POINT and OPEN_PLANAR contours (not regions) likewise. A voxel inside two ROIs goes to the
// later one (a labelmap holds one label), with a warning naming both.
#include <string>
#include <vector>

class vtkRPSegmentationNode;

namespace rp {

struct DicomReferenceSeries;

/// Reads the RTSTRUCT file `path` (or the only one in folder `path`). `referencePath`: the image
/// series its contours were drawn on (folder); "" = the RTSTRUCT's own folder, choosing the
/// series the structure set names when several are there.
bool ReadDicomRtStruct(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                       const std::string& referencePath = "", std::vector<std::string>* warnings = nullptr);

/// The same with the series the contours were drawn on already read (rpDicomReferenceSeries.h).
bool ReadDicomRtStruct(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                       const DicomReferenceSeries& reference, std::vector<std::string>* warnings = nullptr);

}  // namespace rp
