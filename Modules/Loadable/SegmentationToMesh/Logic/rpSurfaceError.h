#pragma once
// Scores a mesh against a known surface (analytic solid or phantom): mesh → truth distances from
// a signed distance function at area-weighted triangle samples, truth → mesh distances from
// points on the true surface, and the mean / RMS / Hausdorff of both.
#include <array>
#include <functional>
#include <vector>

class vtkPolyData;

namespace rp {

using SignedDistanceFunction = std::function<double(const double ras[3])>;

struct SurfaceError {
  double MeanMm = 0;          // symmetric mean: (mesh→truth + truth→mesh) / 2
  double MeshToTruthMeanMm = 0;
  double TruthToMeshMeanMm = 0;
  double RmsMm = 0;
  double HausdorffMm = 0;     // max of both directions
  double Percentile95Mm = 0;  // 95th percentile of the distances of both directions (pooled)
  double SignedMeanMm = 0;    // mesh→truth signed (> 0 = mesh outside the truth)
};

/// `truthPoints` lie on the true surface. `sdf` may be null: then only truth → mesh is used for
/// the mean, and the Hausdorff distance of that direction. With `clipBounds` (xmin, xmax, ymin,
/// ...), mesh samples and truth points outside the box are ignored (e.g. caps where a structure
/// leaves the field of view).
SurfaceError CompareToSurface(vtkPolyData* mesh, const SignedDistanceFunction& sdf,
                              const std::vector<std::array<double, 3>>& truthPoints, const double* clipBounds = nullptr);

/// A mesh against a reference mesh (e.g. a bone surface from another segmentation): distances
/// from the mesh's vertices and triangle centroids (area-weighted) to the reference and back,
/// signed by the side of the reference's closest triangle (> 0 = mesh outside the reference). With `clipBounds`, samples
/// outside the box are ignored on both sides.
SurfaceError CompareMeshes(vtkPolyData* mesh, vtkPolyData* reference, const double* clipBounds = nullptr);

}  // namespace rp
