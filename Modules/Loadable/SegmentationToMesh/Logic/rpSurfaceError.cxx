#include "rpSurfaceError.h"

#include <algorithm>
#include <cmath>

#include <vtkCellArray.h>

#include "rpLabelmapToMesh.h"
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkStaticCellLocator.h>

namespace rp {

namespace {
bool InBox(const double* box, const double p[3]) {
  return !box || (p[0] >= box[0] && p[0] <= box[1] && p[1] >= box[2] && p[1] <= box[3] && p[2] >= box[4] &&
                  p[2] <= box[5]);
}

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(fraction * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return values[k];
}

// Area-weighted samples of a triangle mesh: vertices (a third of their triangles' area each,
// halved) and triangle centroids (half the triangle's area).
struct Samples {
  std::vector<std::array<double, 3>> Points;
  std::vector<double> Weights;
};

Samples SampleMesh(vtkPolyData* mesh) {
  Samples s;
  vtkPoints* points = mesh->GetPoints();
  const vtkIdType np = mesh->GetNumberOfPoints();
  s.Points.resize(static_cast<size_t>(np));
  s.Weights.assign(static_cast<size_t>(np), 0.0);
  for (vtkIdType i = 0; i < np; ++i) points->GetPoint(i, s.Points[static_cast<size_t>(i)].data());
  ForEachTriangle(mesh, [&](const vtkIdType* ids, const double* a, const double* b, const double* c, const double* f) {
    const double area = 0.5 * std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int t = 0; t < 3; ++t) s.Weights[static_cast<size_t>(ids[t])] += area / 6.0;
    s.Points.push_back({(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3});
    s.Weights.push_back(area / 2.0);
  });
  return s;
}
}  // namespace

SurfaceError CompareToSurface(vtkPolyData* mesh, const SignedDistanceFunction& sdf,
                              const std::vector<std::array<double, 3>>& truthPoints, const double* clipBounds) {
  SurfaceError result;
  if (!mesh || mesh->GetNumberOfPolys() == 0) return result;
  double sumSquares = 0, samples = 0;
  std::vector<double> all;  // |distance| of every sample, both directions
  if (sdf) {
    // Mesh → truth: |sdf| at each vertex and triangle centroid, weighted by area.
    const Samples s = SampleMesh(mesh);
    std::vector<double> d(s.Points.size());
    vtkSMPTools::For(0, static_cast<vtkIdType>(d.size()), [&](vtkIdType i0, vtkIdType i1) {
      for (vtkIdType i = i0; i < i1; ++i) d[static_cast<size_t>(i)] = sdf(s.Points[static_cast<size_t>(i)].data());
    });
    double weighted = 0, signedSum = 0, weights = 0;
    for (size_t i = 0; i < d.size(); ++i) {
      if (!InBox(clipBounds, s.Points[i].data())) continue;
      const double w = s.Weights[i];
      weighted += w * std::abs(d[i]);
      signedSum += w * d[i];
      weights += w;
      result.HausdorffMm = std::max(result.HausdorffMm, std::abs(d[i]));
      all.push_back(std::abs(d[i]));
      sumSquares += d[i] * d[i];
      samples += 1;
    }
    result.MeshToTruthMeanMm = weights > 0 ? weighted / weights : 0;
    result.SignedMeanMm = weights > 0 ? signedSum / weights : 0;
  }
  if (!truthPoints.empty()) {
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(mesh);
    locator->BuildLocator();
    std::vector<double> d;
    // FindClosestPoint is not thread-safe on one locator in VTK 9.1: run serially.
    for (size_t i = 0; i < truthPoints.size(); ++i) {
      double p[3] = {truthPoints[i][0], truthPoints[i][1], truthPoints[i][2]}, closest[3], d2;
      if (!InBox(clipBounds, p)) continue;
      vtkIdType cell;
      int sub;
      locator->FindClosestPoint(p, closest, cell, sub, d2);
      d.push_back(std::sqrt(d2));
    }
    double sum = 0;
    for (double v : d) {
      sum += v;
      sumSquares += v * v;
      samples += 1;
      result.HausdorffMm = std::max(result.HausdorffMm, v);
    }
    result.TruthToMeshMeanMm = d.empty() ? 0.0 : sum / static_cast<double>(d.size());
    all.insert(all.end(), d.begin(), d.end());
  }
  result.Percentile95Mm = Percentile(all, 0.95);
  if (sdf && !truthPoints.empty()) {
    result.MeanMm = 0.5 * (result.MeshToTruthMeanMm + result.TruthToMeshMeanMm);
  } else {
    result.MeanMm = sdf ? result.MeshToTruthMeanMm : result.TruthToMeshMeanMm;
  }
  result.RmsMm = samples > 0 ? std::sqrt(sumSquares / samples) : 0;
  return result;
}

SurfaceError CompareMeshes(vtkPolyData* mesh, vtkPolyData* reference, const double* clipBounds) {
  SurfaceError result;
  if (!mesh || !reference || mesh->GetNumberOfPolys() == 0 || reference->GetNumberOfPolys() == 0) return result;
  std::vector<double> all;
  double sumSquares = 0;
  // One direction: weighted mean of |d| (and signed d with `sign`) from `from` samples to `to`.
  auto oneWay = [&](vtkPolyData* from, vtkPolyData* to, bool signedBySide, double& mean) {
    const Samples s = SampleMesh(from);
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(to);
    locator->BuildLocator();
    // Sign from the closest triangle's side (its normal, outward when `to` encloses a positive volume).
    double volume = 0, area = 0;
    MeshVolumeAndArea(to, volume, area);
    const double orientation = volume < 0 ? -1.0 : 1.0;
    vtkNew<vtkGenericCell> cell;
    double weighted = 0, signedSum = 0, weights = 0;
    for (size_t i = 0; i < s.Points.size(); ++i) {
      const double* p = s.Points[i].data();
      if (!InBox(clipBounds, p)) continue;
      double closest[3], d2;
      vtkIdType cellId;
      int sub;
      locator->FindClosestPoint(p, closest, cell, cellId, sub, d2);
      double d = std::sqrt(d2);
      if (signedBySide) {
        double a[3], b[3], c[3];
        vtkPoints* pts = cell->GetPoints();
        pts->GetPoint(0, a), pts->GetPoint(1, b), pts->GetPoint(2, c);
        double n[3];
        TriangleCross(a, b, c, n);
        const double side = (p[0] - closest[0]) * n[0] + (p[1] - closest[1]) * n[1] + (p[2] - closest[2]) * n[2];
        if (side * orientation < 0) d = -d;
      }
      weighted += s.Weights[i] * std::abs(d);
      if (signedBySide) signedSum += s.Weights[i] * d;
      weights += s.Weights[i];
      all.push_back(std::abs(d));
      sumSquares += d * d;
      result.HausdorffMm = std::max(result.HausdorffMm, std::abs(d));
    }
    mean = weights > 0 ? weighted / weights : 0;
    if (signedBySide) result.SignedMeanMm = weights > 0 ? signedSum / weights : 0;
  };
  oneWay(mesh, reference, true, result.MeshToTruthMeanMm);
  oneWay(reference, mesh, false, result.TruthToMeshMeanMm);
  result.MeanMm = 0.5 * (result.MeshToTruthMeanMm + result.TruthToMeshMeanMm);
  result.RmsMm = all.empty() ? 0 : std::sqrt(sumSquares / static_cast<double>(all.size()));
  result.Percentile95Mm = Percentile(all, 0.95);
  return result;
}

}  // namespace rp
