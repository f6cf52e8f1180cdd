#pragma once
// One segment of a labelmap → a closed triangle mesh in RAS.
//
// Default method ("gaussian"): crop to the segment's bounds (padded, so a segment touching the
// volume border still closes), resample the binary mask with a separable Gaussian onto a contour
// grid (GridStep voxels apart: coarser grid = fewer triangles, i.e. decimation by resolution),
// constrain samples on voxel centres to their side of 0.5 (labelled voxels stay inside),
// contour at 0.5 with vtkFlyingEdges3D (normals from the field's gradient), map to RAS, then
// correct the volume: every vertex moves along its normal by (V_labelmap - V_mesh) / area, so the
// mesh encloses the labelmap's volume. Smoothing before contouring keeps the surface closed and
// manifold (it is an isosurface of a field that is zero on the padded border).
//
// "sinc": vtkDiscreteFlyingEdges3D → vtkWindowedSincPolyDataFilter (VTK 9.1's Hamming window
// shrinks/grows the surface) → the same volume correction. "slicer": Slicer's default pipeline
// without correction (the baseline of the benchmark). "none": discrete flying edges only.
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "rpProgress.h"

class vtkImageData;
class vtkMatrix4x4;

namespace rp {

enum class MeshMethod { Gaussian, WindowedSinc, SlicerDefault, Discrete };

bool ParseMeshMethod(const std::string& text, MeshMethod& method);
const char* MeshMethodName(MeshMethod method);

struct MeshOptions {
  MeshMethod Method = MeshMethod::Gaussian;
  /// Gaussian: standard deviation in voxels (index space, each axis). Samples on voxel centres
  /// are constrained to the labelmap's side of the 0.5 level, so one-voxel structures survive
  /// any sigma.
  double Sigma = 1.0;
  /// Gaussian: contour grid spacing in voxels per axis (1 = voxel grid; 2 = 4x fewer triangles).
  /// The effective sigma is raised to 0.4*step so the coarse grid does not alias.
  double GridStep[3] = {1.0, 1.0, 1.0};
  /// Windowed sinc (methods sinc and slicer).
  int SincIterations = 20;
  double SincPassBand = 0.01;
  /// Extra decimation after contouring: fraction of triangles removed (0 = none), by
  /// topology-preserving edge collapses (rpManifoldDecimation: the mesh stays closed).
  double DecimationFraction = 0.0;
  /// Move vertices along normals so the mesh volume equals the labelmap volume.
  bool CorrectVolume = true;
};

struct MeshStats {
  int Label = 0;
  long LabelVoxels = 0;
  long Triangles = 0;
  long Points = 0;
  double LabelVolumeMm3 = 0;    // voxel count x voxel volume
  double MeshVolumeMm3 = 0;     // enclosed by the mesh (divergence theorem)
  double VolumeErrorPercent = 0;  // mesh vs labelmap
  double AreaMm2 = 0;
  double VolumeCorrectionMm = 0;  // normal offset applied by the volume correction
  long BoundaryEdges = 0;
  long NonManifoldEdges = 0;
  long NonManifoldVertices = 0;
  bool Watertight = false;         // no boundary and no non-manifold edges
  bool Manifold = false;           // watertight and every vertex one closed fan
  /// How the mesh was made: "gaussian", "gaussian, grid 2.4 voxels, edge collapse", ...
  std::string Method;
  /// Largest deviation from the full-resolution surface (sampled, both ways; -1 = not measured).
  double MaxDeviationMm = -1;
  /// Level of detail: the triangle budget (0 = none) and whether the mesh meets it.
  long BudgetTriangles = 0;
  bool WithinBudget = true;
  /// Components left out of a level of detail that could not hold them all (smallest first).
  long DroppedComponents = 0;
  double DroppedVolumeMm3 = 0;
  bool TouchesBorder = false;      // segment reaches the volume border (closed by padding)
  double GridStep[3] = {1, 1, 1};  // grid actually used
  double Seconds = 0;
  std::vector<std::string> Warnings;
};

/// Meshes voxels == label of `labelmap` (origin 0, spacing 1, integer scalars) into `output`
/// (RAS, outward normals in point data "Normals"). Returns false with `error` when the segment
/// is empty or the input is unusable; `output` is then left empty.
bool LabelmapToMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const MeshOptions& options,
                    vtkPolyData* output, MeshStats& stats, std::string& error,
                    const ProgressCallback& progress = nullptr);

/// Pieces of the pipeline, for levels of detail built on top of it (rpMeshLevelOfDetail):
/// area-weighted vertex normals; vertices moved along them until the mesh encloses
/// `targetVolume` (returns the offset, mm); stats of a finished mesh.
void ComputeMeshNormals(vtkPolyData* mesh);
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume);
void FillMeshStats(vtkPolyData* mesh, MeshStats& stats);

/// (b - a) x (c - a): twice the triangle's area along its normal.
inline void TriangleCross(const double a[3], const double b[3], const double c[3], double f[3]) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  f[0] = u[1] * v[2] - u[2] * v[1], f[1] = u[2] * v[0] - u[0] * v[2], f[2] = u[0] * v[1] - u[1] * v[0];
}

/// Calls `visit(ids, a, b, c, cross)` for every triangle (3-point polygon; other cells are
/// skipped) of `mesh`: its corner ids, corner points and TriangleCross(a, b, c). The one walk
/// that vertex normals, orientation checks and area-weighted sampling share.
template <class Visit>
void ForEachTriangle(vtkPolyData* mesh, Visit&& visit) {
  vtkCellArray* polys = mesh->GetPolys();
  vtkPoints* points = mesh->GetPoints();
  if (!polys || !points) return;
  vtkIdType n;
  const vtkIdType* ids;
  double a[3], b[3], c[3], cross[3];
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3) continue;
    points->GetPoint(ids[0], a), points->GetPoint(ids[1], b), points->GetPoint(ids[2], c);
    TriangleCross(a, b, c, cross);
    visit(ids, a, b, c, cross);
  }
}

/// Edge topology of a triangle mesh: edges used by one triangle (holes) and by more than two.
void CountBadEdges(vtkPolyData* mesh, long& boundaryEdges, long& nonManifoldEdges);
/// Vertices whose triangles do not form one closed fan (two sheets touching at a point).
long CountNonManifoldVertices(vtkPolyData* mesh);
struct MeshTopology {
  long BoundaryEdges = 0, NonManifoldEdges = 0, NonManifoldVertices = 0;
};
/// All three counts in one parallel pass over every vertex's fan (the edges counted from both
/// ends' fans instead of one global sort of every edge); the same numbers as CountBadEdges and
/// CountNonManifoldVertices.
MeshTopology CountTopology(vtkPolyData* mesh);
/// Enclosed volume (mm³, positive for outward orientation) and area of a triangle mesh.
void MeshVolumeAndArea(vtkPolyData* mesh, double& volume, double& area);

}  // namespace rp
