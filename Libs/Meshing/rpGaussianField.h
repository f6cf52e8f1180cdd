#pragma once
// The field the default ("gaussian") surface is the 0.5 level of: one label's binary mask blurred
// by a separable Gaussian and resampled onto the contour grid, with samples on voxel centres kept
// on their voxel's side of 0.5 (so one-voxel structures survive any blur).
#include "rpLabelScan.h"

namespace rp {

/// How far from the 0.5 level the constraint puts voxel-centre samples.
constexpr float GaussianConstraintMargin = 0.01f;

/// Fills `field` (outDims[0] x outDims[1] x outDims[2], x fastest) with the blurred mask of `label`
/// (bounds `b`) at grid positions gridStart + o * step (voxel index units), Gaussian standard
/// deviation sigma (voxels) per axis.
void ResampleLabelGaussian(vtkImageData* labelmap, long label, const LabelBounds& b, const double gridStart[3],
                           const double step[3], const int outDims[3], const double sigma[3], float* field);

}  // namespace rp
