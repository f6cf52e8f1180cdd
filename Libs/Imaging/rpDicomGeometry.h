#pragma once
// Internal to RoboPlanDicom: the geometry of a DICOM stack from its images' headers: which
// images form one stack, their order along the slice normal, the spacing, what makes a series
// irregular or unreadable (gantry tilt, duplicate positions, missing slices), the IJK-to-LPS
// matrix, and resampling an irregular stack onto a regular grid.
#include <string>
#include <vector>

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include "rpDicomHeader.h"

namespace rp::dicom {

/// Images of one stack share orientation, image size and pixel spacing.
bool SameStack(const SliceHeader& a, const SliceHeader& b);
/// Splits the images of one series into stacks, in the order their first image was found.
std::vector<std::vector<SliceHeader>> SplitIntoStacks(std::vector<SliceHeader> headers);
/// The files of the headers, each once (in order).
std::vector<std::string> DistinctFiles(const std::vector<SliceHeader>& headers);

// Slice order and spacing of one stack from its headers.
struct SeriesGeometry {
  std::vector<size_t> Order;         // header indices sorted along the normal
  std::vector<double> Positions;     // sorted positions along the normal
  double Normal[3] = {0, 0, 1};
  double Spacing = 1.0;              // median gap
  double MinGap = 1.0;
  bool Irregular = false;            // missing slice / uneven spacing
  std::string IrregularMessage;
  std::string Problem;               // refused outright
};

/// Order, spacing and what is wrong with a stack (`tolerance`: relative, on the gaps).
SeriesGeometry AnalyzeGeometry(const std::vector<SliceHeader>& headers, double tolerance);
/// i along a row (IOP row direction, column spacing), j down the columns, k along the normal;
/// IJK-to-LPS from the first header, its origin moved to `firstPosition` along the normal (a
/// resampled grid's first slice).
void StackMatrix(const SliceHeader& h0, const SeriesGeometry& g, double spacing, double firstPosition,
                 double ijkToLPS[16]);
/// An irregular stack resampled along the normal onto a regular grid whose spacing is about the
/// smallest gap (linear, float); `positions` and `spacing` receive the new grid's.
vtkSmartPointer<vtkImageData> ResampleAlongNormal(vtkImageData* stack, const SeriesGeometry& g,
                                                  std::vector<double>& positions, double& spacing);

}  // namespace rp::dicom
