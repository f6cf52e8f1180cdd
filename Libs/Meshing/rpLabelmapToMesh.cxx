#include "rpLabelmapToMesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkSmartPointer.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include "rpGaussianField.h"
#include "rpLabelScan.h"
#include "rpManifoldDecimation.h"

namespace rp {

bool ParseMeshMethod(const std::string& text, MeshMethod& method) {
  if (text == "gaussian") method = MeshMethod::Gaussian;
  else if (text == "sinc") method = MeshMethod::WindowedSinc;
  else if (text == "slicer") method = MeshMethod::SlicerDefault;
  else if (text == "discrete" || text == "none") method = MeshMethod::Discrete;
  else return false;
  return true;
}

const char* MeshMethodName(MeshMethod method) {
  switch (method) {
    case MeshMethod::Gaussian: return "gaussian";
    case MeshMethod::WindowedSinc: return "sinc";
    case MeshMethod::SlicerDefault: return "slicer";
    case MeshMethod::Discrete: return "discrete";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

// The enclosed volume and area of the mesh as it stands, once measured (each measure is a pass
// over every triangle): Known is cleared by any step that moves points or flips triangles.
struct Measured {
  bool Known = false;
  double Volume = 0, Area = 0;
  void Of(vtkPolyData* mesh) {
    if (!Known) MeshVolumeAndArea(mesh, Volume, Area);
    Known = true;
  }
};

double Determinant3(const vtkMatrix4x4* m) {
  double a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = m->GetElement(r, c);
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

bool GaussianMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const LabelBounds& b,
                  const MeshOptions& options, vtkPolyData* output, MeshStats& stats, Measured& measured,
                  std::string& error, const ProgressCallback& progress) {
  int dims[3];
  labelmap->GetDimensions(dims);
  double sigma[3], start[3], step[3];
  int outDims[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = std::max(0.25, options.GridStep[a]);
    sigma[a] = std::max({options.Sigma, 0.4 * step[a], 0.2});
    const double pad = std::ceil(3.0 * sigma[a]) + step[a];
    start[a] = b.Lo[a] - pad;
    outDims[a] = static_cast<int>(std::ceil((b.Hi[a] + pad - start[a]) / step[a])) + 1;
    stats.GridStep[a] = step[a];
  }
  const double cells = static_cast<double>(outDims[0]) * outDims[1] * outDims[2];
  if (cells > 1.5e9) {
    error = "contour grid of " + std::to_string(static_cast<long long>(cells)) + " samples is too large; raise the grid step";
    return false;
  }
  if (progress) progress(0.1, "resampling");
  vtkNew<vtkImageData> field;
  field->SetDimensions(outDims);
  field->AllocateScalars(VTK_FLOAT, 1);
  float* f = static_cast<float*>(field->GetScalarPointer());
  ResampleLabelGaussian(labelmap, label, b, start, step, outDims, sigma, f);
  if (progress) progress(0.4, "contouring");
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(field);
  contour->SetValue(0, 0.5);
  contour->ComputeNormalsOn();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  output->ShallowCopy(contour->GetOutput());
  if (output->GetNumberOfPolys() == 0) {
    error = "the smoothed segment has no surface at the 0.5 level (structures thinner than the smoothing; "
            "lower the smoothing or the grid step)";
    return false;
  }
  if (progress) progress(0.7, "mapping to RAS");
  GridToRAS(output, ijkToRAS, start, step, true);
  measured.Known = OrientOutward(output, &measured.Volume, &measured.Area);
  return true;
}

bool DiscreteMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const LabelBounds& b,
                  const MeshOptions& options, vtkPolyData* output, MeshStats& stats, Measured& measured,
                  std::string& error, const ProgressCallback& progress) {
  int dims[3], start[3], size[3];
  labelmap->GetDimensions(dims);
  for (int a = 0; a < 3; ++a) {
    start[a] = b.Lo[a] - 1;
    size[a] = b.Hi[a] - b.Lo[a] + 3;
  }
  vtkNew<vtkImageData> mask;
  mask->SetDimensions(size);
  mask->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  ExtractLabelMask(labelmap, label, start, size, static_cast<unsigned char*>(mask->GetScalarPointer()));
  if (progress) progress(0.2, "contouring");
  vtkNew<vtkDiscreteFlyingEdges3D> contour;
  contour->SetInputData(mask);
  contour->SetValue(0, 1);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkSmartPointer<vtkPolyData> mesh = contour->GetOutput();
  if (mesh->GetNumberOfPolys() == 0) {
    error = "discrete contouring gave no triangles";
    return false;
  }
  if (options.Method == MeshMethod::WindowedSinc || options.Method == MeshMethod::SlicerDefault) {
    if (progress) progress(0.4, "smoothing");
    vtkNew<vtkWindowedSincPolyDataFilter> smoother;
    smoother->SetInputData(mesh);
    smoother->SetNumberOfIterations(options.SincIterations);
    smoother->SetPassBand(options.SincPassBand);
    smoother->BoundarySmoothingOff();
    smoother->FeatureEdgeSmoothingOff();
    smoother->NonManifoldSmoothingOn();
    smoother->NormalizeCoordinatesOn();
    smoother->Update();
    // On tiny meshes (a few voxels) the sinc filter can collapse or explode the surface.
    double before = 0, after = 0, area = 0;
    MeshVolumeAndArea(mesh, before, area);
    MeshVolumeAndArea(smoother->GetOutput(), after, area);
    if (std::isfinite(after) && std::abs(after) > 0.5 * std::abs(before) && std::abs(after) < 2.0 * std::abs(before)) {
      mesh = smoother->GetOutput();
    } else {
      stats.Warnings.push_back("windowed sinc collapsed the surface (too few voxels): kept the unsmoothed surface");
    }
  }
  output->ShallowCopy(mesh);
  // Own the points before moving them (the filter output may share them).
  vtkNew<vtkPoints> points;
  points->DeepCopy(mesh->GetPoints());
  output->SetPoints(points);
  const double origin[3] = {static_cast<double>(start[0]), static_cast<double>(start[1]), static_cast<double>(start[2])};
  const double unit[3] = {1, 1, 1};
  if (progress) progress(0.7, "mapping to RAS");
  GridToRAS(output, ijkToRAS, origin, unit, false);
  if (options.Method == MeshMethod::SlicerDefault) {
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(output);
    normals->ConsistencyOn();
    normals->SplittingOff();
    normals->Update();
    output->ShallowCopy(normals->GetOutput());
  } else {
    measured.Known = OrientOutward(output, &measured.Volume, &measured.Area);
    ComputeMeshNormals(output);
  }
  return true;
}

void Decimate(vtkPolyData* mesh, double fraction, MeshStats& stats) {
  if (fraction <= 0) return;
  DecimationResult result;
  const long target = static_cast<long>(std::ceil((1.0 - std::min(fraction, 0.99)) * mesh->GetNumberOfPolys()));
  if (!DecimateManifold(mesh, target, 0.0, result)) {
    stats.Warnings.push_back("decimation skipped: the mesh is not a closed manifold");
    return;
  }
  ComputeMeshNormals(mesh);
  stats.Method += ", edge collapse";
}

}  // namespace

void FillMeshStats(vtkPolyData* mesh, MeshStats& stats) {
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  FillMeshStats(mesh, stats, volume, area);
}

void FillMeshStats(vtkPolyData* mesh, MeshStats& stats, double volume, double area) {
  stats.Triangles = mesh->GetNumberOfPolys();
  stats.Points = mesh->GetNumberOfPoints();
  stats.MeshVolumeMm3 = volume;
  stats.AreaMm2 = area;
  stats.VolumeErrorPercent =
      stats.LabelVolumeMm3 > 0 ? 100.0 * (stats.MeshVolumeMm3 - stats.LabelVolumeMm3) / stats.LabelVolumeMm3 : 0.0;
  const MeshTopology topology = CountTopology(mesh);
  stats.BoundaryEdges = topology.BoundaryEdges;
  stats.NonManifoldEdges = topology.NonManifoldEdges;
  stats.NonManifoldVertices = topology.NonManifoldVertices;
  stats.Watertight = stats.Triangles > 0 && stats.BoundaryEdges == 0 && stats.NonManifoldEdges == 0;
  stats.Manifold = stats.Watertight && stats.NonManifoldVertices == 0;
}


bool LabelmapToMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const MeshOptions& options,
                    vtkPolyData* output, MeshStats& stats, std::string& error, const ProgressCallback& progress) {
  const auto t0 = Clock::now();
  stats = MeshStats();
  stats.Label = label;
  output->Initialize();
  if (!labelmap || !labelmap->GetPointData()->GetScalars() || labelmap->GetNumberOfPoints() == 0) {
    error = "the segmentation has no labelmap";
    return false;
  }
  if (!HasIntegerScalars(labelmap) || labelmap->GetNumberOfScalarComponents() != 1) {
    error = "the labelmap must hold one integer label per voxel";
    return false;
  }
  if (!ijkToRAS || std::abs(Determinant3(ijkToRAS)) < 1e-12) {
    error = "the labelmap's IJK-to-RAS matrix is missing or singular";
    return false;
  }
  if (options.Sigma < 0 || options.GridStep[0] <= 0 || options.GridStep[1] <= 0 || options.GridStep[2] <= 0 ||
      options.DecimationFraction < 0 || options.DecimationFraction >= 1) {
    error = "invalid mesh options (sigma >= 0, grid step > 0, decimation in [0, 1))";
    return false;
  }
  int dims[3];
  labelmap->GetDimensions(dims);
  const LabelBounds b = CachedLabelBounds(labelmap, label);
  stats.LabelVoxels = b.Count;
  const double voxelVolume = std::abs(Determinant3(ijkToRAS));
  stats.LabelVolumeMm3 = static_cast<double>(b.Count) * voxelVolume;
  if (b.Empty()) {
    error = "segment with label " + std::to_string(label) + " is empty (no voxels)";
    return false;
  }
  for (int a = 0; a < 3; ++a) stats.TouchesBorder = stats.TouchesBorder || b.Lo[a] == 0 || b.Hi[a] == dims[a] - 1;
  if (stats.TouchesBorder) stats.Warnings.push_back("segment touches the volume border: closed by padding (flat cap)");

  bool ok = false;
  Measured measured;
  stats.Method = MeshMethodName(options.Method);
  if (options.Method == MeshMethod::Gaussian) {
    ok = GaussianMesh(labelmap, ijkToRAS, label, b, options, output, stats, measured, error, progress);
    if (ok) measured.Of(output);
    if (!ok || measured.Volume < 0.5 * stats.LabelVolumeMm3) {
      // Should not happen with the voxel-centre constraint; kept as a safety net.
      stats.Warnings.push_back("gaussian surface failed (" + (ok ? "lost half the volume" : error) +
                               "): used the discrete surface");
      MeshOptions fallback = options;
      fallback.Method = MeshMethod::Discrete;
      stats.Method = "discrete (gaussian failed)";
      error.clear();
      measured = Measured();
      ok = DiscreteMesh(labelmap, ijkToRAS, label, b, fallback, output, stats, measured, error, progress);
    }
  } else {
    ok = DiscreteMesh(labelmap, ijkToRAS, label, b, options, output, stats, measured, error, progress);
  }
  if (!ok) {
    output->Initialize();
    return false;
  }
  if (options.DecimationFraction > 0) {
    if (progress) progress(0.8, "decimating");
    Decimate(output, options.DecimationFraction, stats);
    measured = Measured();
  }
  if (options.CorrectVolume && options.Method != MeshMethod::SlicerDefault) {
    measured.Of(output);
    const double volume = measured.Volume, area = measured.Area;
    const double mismatch = std::abs(volume - stats.LabelVolumeMm3) / stats.LabelVolumeMm3;
    // The offset that would fix the volume. More than half a voxel means the mesh lacks whole
    // structures below the smoothing scale (noise specks, pinholes): a global offset would
    // distort the rest, so the mismatch is reported instead.
    double minSpacing = 1e300;
    for (int a = 0; a < 3; ++a) {
      double len = 0;
      for (int r = 0; r < 3; ++r) len += ijkToRAS->GetElement(r, a) * ijkToRAS->GetElement(r, a);
      minSpacing = std::min(minSpacing, std::sqrt(len));
    }
    const double offset = area > 0 ? std::abs(stats.LabelVolumeMm3 - volume) / area : 0.0;
    if (offset > 0.5 * minSpacing && stats.LabelVoxels > 64) {
      stats.Warnings.push_back("mesh volume differs from the labelmap by " +
                               std::to_string(static_cast<int>(std::round(100 * mismatch))) +
                               " % (noise or structures below the smoothing scale): volume not corrected; "
                               "clean the segment first (keep largest, fill holes, opening)");
    } else {
      if (progress) progress(0.9, "volume correction");
      stats.VolumeCorrectionMm = CorrectMeshVolume(output, stats.LabelVolumeMm3, measured.Volume, measured.Area);
    }
  }
  measured.Of(output);
  FillMeshStats(output, stats, measured.Volume, measured.Area);
  if (!stats.Watertight) {
    stats.Warnings.push_back("mesh is not watertight: " + std::to_string(stats.BoundaryEdges) + " boundary and " +
                             std::to_string(stats.NonManifoldEdges) + " non-manifold edges");
  } else if (!stats.Manifold) {
    stats.Warnings.push_back("mesh has " + std::to_string(stats.NonManifoldVertices) + " non-manifold vertices");
  }
  stats.Seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (progress) progress(1.0, "done");
  return true;
}

}  // namespace rp
