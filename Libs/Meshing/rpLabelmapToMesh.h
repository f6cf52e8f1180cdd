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

#include "rpMeshMeasures.h"
#include "rpProgress.h"
#include "rpSurfaceCorrection.h"

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

/// Stats of a finished mesh (triangles, volume against the label's, area, topology).
void FillMeshStats(vtkPolyData* mesh, MeshStats& stats);
/// The same with the mesh's enclosed volume and area already measured.
void FillMeshStats(vtkPolyData* mesh, MeshStats& stats, double volume, double area);

}  // namespace rp
