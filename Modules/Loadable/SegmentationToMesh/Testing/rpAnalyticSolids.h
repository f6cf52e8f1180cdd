#pragma once
// Analytic solids with exact signed distances and volumes, rasterized into labelmaps (a voxel
// is inside when its centre is), for accuracy tests with known answers.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpSurfaceError.h"

class vtkRPSegmentationNode;

namespace rp::test {

struct AnalyticSolid {
  std::string Name;
  SignedDistanceFunction SDF;  // RAS mm, < 0 inside
  double Volume = 0;           // mm³
  std::vector<std::array<double, 3>> SurfacePoints;
};

AnalyticSolid Sphere(const std::array<double, 3>& center, double radius);
AnalyticSolid Ellipsoid(const std::array<double, 3>& center, const std::array<double, 3>& semiAxes);
AnalyticSolid Torus(const std::array<double, 3>& center, double majorRadius, double minorRadius);  // axis z
AnalyticSolid Box(const std::array<double, 3>& lo, const std::array<double, 3>& hi);

/// Axis-aligned grid (IJKToRAS = diag(spacing) + origin): voxels inside the solid get `label`.
vtkSmartPointer<vtkRPSegmentationNode> Rasterize(const AnalyticSolid& solid, const std::array<int, 3>& dims,
                                                 const std::array<double, 3>& spacing,
                                                 const std::array<double, 3>& origin, int label = 1,
                                                 const std::string& tissueClass = "bone");

/// Dice overlap of voxels == labelA in a and == labelB in b (same dimensions).
double Dice(vtkRPSegmentationNode* a, int labelA, vtkRPSegmentationNode* b, int labelB);
long CountLabel(vtkRPSegmentationNode* node, int label);

}  // namespace rp::test
