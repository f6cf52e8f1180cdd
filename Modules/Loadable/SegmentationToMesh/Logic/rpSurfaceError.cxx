#include "rpSurfaceError.h"

#include <algorithm>
#include <cmath>

#include <vtkCellArray.h>
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
}  // namespace

SurfaceError CompareToSurface(vtkPolyData* mesh, const SignedDistanceFunction& sdf,
                              const std::vector<std::array<double, 3>>& truthPoints, const double* clipBounds) {
  SurfaceError result;
  if (!mesh || mesh->GetNumberOfPolys() == 0) return result;
  double sumSquares = 0, samples = 0;
  std::vector<double> pooled;  // |distance| of every sample of both directions
  if (sdf) {
    // Mesh → truth: |sdf| at each vertex and triangle centroid, weighted by area (vertices carry a
    // third of their triangles' area each, centroids the triangle's own area).
    vtkCellArray* polys = mesh->GetPolys();
    vtkPoints* points = mesh->GetPoints();
    const vtkIdType np = mesh->GetNumberOfPoints();
    std::vector<double> vertexArea(static_cast<size_t>(np), 0.0);
    std::vector<std::array<double, 4>> centroids;  // x, y, z, area
    centroids.reserve(static_cast<size_t>(mesh->GetNumberOfPolys()));
    vtkIdType n;
    const vtkIdType* ids;
    double a[3], b[3], c[3];
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
      if (n != 3) continue;
      points->GetPoint(ids[0], a), points->GetPoint(ids[1], b), points->GetPoint(ids[2], c);
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double f[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double area = 0.5 * std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      for (int t = 0; t < 3; ++t) vertexArea[static_cast<size_t>(ids[t])] += area / 6.0;
      centroids.push_back({(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3, area / 2.0});
    }
    const size_t total = static_cast<size_t>(np) + centroids.size();
    std::vector<double> d(total);
    vtkSMPTools::For(0, static_cast<vtkIdType>(total), [&](vtkIdType i0, vtkIdType i1) {
      double p[3];
      for (vtkIdType i = i0; i < i1; ++i) {
        if (i < np) {
          points->GetPoint(i, p);
        } else {
          const auto& q = centroids[static_cast<size_t>(i - np)];
          p[0] = q[0], p[1] = q[1], p[2] = q[2];
        }
        d[static_cast<size_t>(i)] = sdf(p);
      }
    });
    double weighted = 0, signedSum = 0, weights = 0;
    std::vector<char> keep(total, 1);
    if (clipBounds) {
      for (size_t i = 0; i < total; ++i) {
        double p[3];
        if (i < static_cast<size_t>(np)) {
          points->GetPoint(static_cast<vtkIdType>(i), p);
        } else {
          const auto& q = centroids[i - static_cast<size_t>(np)];
          p[0] = q[0], p[1] = q[1], p[2] = q[2];
        }
        keep[i] = InBox(clipBounds, p);
      }
    }
    for (size_t i = 0; i < total; ++i) {
      if (!keep[i]) continue;
      const double w = i < static_cast<size_t>(np) ? vertexArea[i] : centroids[i - static_cast<size_t>(np)][3];
      weighted += w * std::abs(d[i]);
      signedSum += w * d[i];
      weights += w;
      result.HausdorffMm = std::max(result.HausdorffMm, std::abs(d[i]));
      pooled.push_back(std::abs(d[i]));
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
      pooled.push_back(v);
    }
    result.TruthToMeshMeanMm = d.empty() ? 0.0 : sum / static_cast<double>(d.size());
  }
  if (sdf && !truthPoints.empty()) {
    result.MeanMm = 0.5 * (result.MeshToTruthMeanMm + result.TruthToMeshMeanMm);
  } else {
    result.MeanMm = sdf ? result.MeshToTruthMeanMm : result.TruthToMeshMeanMm;
  }
  result.RmsMm = samples > 0 ? std::sqrt(sumSquares / samples) : 0;
  if (!pooled.empty()) {
    auto at = pooled.begin() + static_cast<std::ptrdiff_t>(0.95 * (pooled.size() - 1));
    std::nth_element(pooled.begin(), at, pooled.end());
    result.Percentile95Mm = *at;
  }
  return result;
}

}  // namespace rp
