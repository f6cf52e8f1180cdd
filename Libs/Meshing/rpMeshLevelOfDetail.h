#pragma once
// Levels of detail that hold on any labelmap: a mesh within a triangle budget (and/or a maximum
// deviation from the full-resolution surface), closed and manifold, whatever the segment is
// (thin ribs, one-voxel plates, hundreds of components, a segment filling the volume's border).
// A fallback chain that always ends within the budget:
//  1. the gaussian surface on a coarser contour grid (triangles ~ 1 / step²), the step searched
//     (a grid so coarse that the surface breaks counts as too coarse);
//  2. topology-preserving edge collapses (rpManifoldDecimation) from the best closed manifold
//     mesh found, down to the budget;
//  3. when the components are more than the budget can hold (a tetrahedron each at least), the
//     smallest components are left out, and the stats say how many and how much volume.
// The stats say what the mesh is: triangles, the method chain, the largest deviation from the
// full-resolution surface (sampled both ways), whether it meets the budget.
#include <string>

#include "rpLabelmapToMesh.h"
#include "rpProgress.h"

class vtkImageData;
class vtkMatrix4x4;
class vtkPolyData;

namespace rp {

/// A target triangle count and/or a maximum deviation from the full-resolution surface (mm).
/// 0 = no target. With both, the triangle budget wins and the deviation is reported.
struct LevelOfDetail {
  long TargetTriangles = 0;
  double MaxErrorMm = 0.0;
};

/// Meshes `label` (see LabelmapToMesh) at a level of detail. `fullResolution`, when given, is the
/// segment's mesh at `options` (e.g. the display mesh, already built, with its stats): it is the
/// reference the deviation is measured from, and is not built again. Returns false only when the
/// segment cannot be meshed at all (empty, unusable input).
bool LabelmapToMeshLOD(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, MeshOptions options,
                       const LevelOfDetail& lod, vtkPolyData* output, MeshStats& stats, std::string& error,
                       const ProgressCallback& progress = nullptr, vtkPolyData* fullResolution = nullptr,
                       const MeshStats* fullResolutionStats = nullptr);

/// Vertices of a surface whose distance MaxSurfaceDeviation measures, at most (every k-th).
constexpr size_t MaxDeviationSamples = 20000;
/// Largest distance between two surfaces: from every vertex of each (every k-th vertex, at most
/// MaxDeviationSamples, of a larger one) to the closest point of the other. -1 when either is empty.
double MaxSurfaceDeviation(vtkPolyData* mesh, vtkPolyData* reference);

}  // namespace rp
