#pragma once
// Where a label lies in a labelmap: its bounds and voxel count (scanned in parallel, once per
// labelmap version and label), and its binary mask over a box. The first step of meshing a label.
#include <vtkImageData.h>

namespace rp {

struct LabelBounds {
  int Lo[3] = {0, 0, 0}, Hi[3] = {-1, -1, -1};  // inclusive voxel index box
  long Count = 0;                                // voxels == label
  bool Empty() const { return this->Count == 0; }
};

/// The bounds of voxels == label. A level of detail contours the same label on several grids, and
/// each scan reads the whole volume (78 M voxels for 512x512x300): the result is kept per thread,
/// keyed by the image and its modification time (VTK's global counter).
LabelBounds CachedLabelBounds(vtkImageData* labelmap, long label);

/// Whether the image's scalars are an integer type (a labelmap's).
bool HasIntegerScalars(vtkImageData* image);

/// Binary mask (1 = label) of the box of `size` voxels from `start` (voxels outside the image are 0).
void ExtractLabelMask(vtkImageData* labelmap, long label, const int start[3], const int size[3], unsigned char* mask);

}  // namespace rp
