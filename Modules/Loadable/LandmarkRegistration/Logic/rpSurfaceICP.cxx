#include "rpSurfaceICP.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <vtkCell.h>
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolygon.h>
#include <vtkStaticCellLocator.h>

namespace rp {

namespace {

// One point-to-plane step: the small rigid motion (ω, τ) minimizing Σ((m + ω×m + τ − q)·n)²,
// applied as a proper rotation. A tiny damping keeps sliding directions (planes, cylinders)
// from making the 6x6 system singular.
SimilarityTransform PointToPlaneStep(const PointList& moved, const PointList& closest, const PointList& normals) {
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (size_t i = 0; i < moved.size(); ++i) {
    Eigen::Matrix<double, 6, 1> row;
    row << moved[i].cross(normals[i]), normals[i];
    a.noalias() += row * row.transpose();
    b += row * (closest[i] - moved[i]).dot(normals[i]);
  }
  a.diagonal().array() += 1e-12 * a.trace();
  const Eigen::Matrix<double, 6, 1> x = a.ldlt().solve(b);
  SimilarityTransform step;
  const Eigen::Vector3d omega = x.head<3>();
  if (omega.norm() > 0) step.Rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  step.Translation = x.tail<3>();
  return step;
}

}  // namespace

SurfaceICPResult RefineWithSurfaceICP(const PointList& digitized, vtkPolyData* surface,
                                      const SimilarityTransform& initial, const SurfaceICPOptions& options) {
  SurfaceICPResult result;
  result.Transform = initial;
  if (!surface || surface->GetNumberOfCells() == 0) {
    result.Error = "the model has no surface cells";
    return result;
  }
  if (!(options.InlierFraction > 0 && options.InlierFraction <= 1)) {
    result.Error = "the inlier fraction must be in (0, 1]";
    return result;
  }
  const size_t n = digitized.size();
  const size_t keep = static_cast<size_t>(std::ceil(options.InlierFraction * static_cast<double>(n)));
  if (keep < 3) {
    result.Error = "ICP needs at least 3 kept surface points (" + std::to_string(n) + " digitized)";
    return result;
  }
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(surface);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;

  PointList moved(n), closest(n), normals(n);
  std::vector<double> distance2(n);
  std::vector<size_t> order(n);
  PointList keptFrom(keep), keptMoved(keep), keptTo(keep), keptNormals(keep);
  auto match = [&](const SimilarityTransform& t) {
    for (size_t i = 0; i < n; ++i) {
      moved[i] = t.Apply(digitized[i]);
      double x[3] = {moved[i][0], moved[i][1], moved[i][2]}, c[3];
      vtkIdType cellId = -1;
      int subId;
      double d2;
      locator->FindClosestPoint(x, c, cell, cellId, subId, d2);
      closest[i] = Eigen::Vector3d(c[0], c[1], c[2]);
      distance2[i] = d2;
      double normal[3] = {0, 0, 0};
      if (cellId >= 0 && cell->GetNumberOfPoints() >= 3) vtkPolygon::ComputeNormal(cell->GetPoints(), normal);
      normals[i] = Eigen::Vector3d(normal[0], normal[1], normal[2]);
    }
    std::iota(order.begin(), order.end(), size_t{0});
    std::nth_element(order.begin(), order.begin() + static_cast<long>(keep - 1), order.end(),
                     [&](size_t a, size_t b) { return distance2[a] < distance2[b]; });
  };

  match(result.Transform);
  for (result.Iterations = 0; result.Iterations < options.MaximumIterations;) {
    for (size_t k = 0; k < keep; ++k) {
      keptFrom[k] = digitized[order[k]];
      keptMoved[k] = moved[order[k]];
      keptTo[k] = closest[order[k]];
      keptNormals[k] = normals[order[k]];
    }
    SimilarityTransform next;
    if (options.PointToPlane) {
      next = PointToPlaneStep(keptMoved, keptTo, keptNormals).Compose(result.Transform);
    } else if (!SolvePairedPoints(keptFrom.data(), keptTo.data(), nullptr, keep, RegistrationMode::Rigid, next)) {
      result.Error = "the kept surface points have no spread";
      return result;
    }
    ++result.Iterations;
    double largestMove = 0;
    for (size_t i = 0; i < n; ++i) largestMove = std::max(largestMove, (next.Apply(digitized[i]) - moved[i]).norm());
    result.Transform = next;
    match(result.Transform);
    if (largestMove < options.ToleranceMM) break;
  }
  double inlierSum = 0, allSum = 0;
  for (size_t k = 0; k < n; ++k) allSum += distance2[k];
  for (size_t k = 0; k < keep; ++k) inlierSum += distance2[order[k]];
  result.Inliers = keep;
  result.InlierRMS = std::sqrt(inlierSum / static_cast<double>(keep));
  result.AllRMS = std::sqrt(allSum / static_cast<double>(n));
  result.Ok = true;
  return result;
}

}  // namespace rp
