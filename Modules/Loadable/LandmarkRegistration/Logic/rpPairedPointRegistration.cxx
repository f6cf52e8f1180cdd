#include "rpPairedPointRegistration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace rp {

namespace {

std::string Format(const char* format, double a, double b = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), format, a, b);
  return buffer;
}

bool AllFinite(const PointList& points) {
  for (const auto& p : points)
    if (!p.allFinite()) return false;
  return true;
}

// First pair of points closer than `fraction` of the set's RMS radius, or {-1,-1}.
std::pair<int, int> FindCoincident(const PointList& points, double fraction) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  double meanSquare = 0;
  for (const auto& p : points) meanSquare += (p - centroid).squaredNorm();
  meanSquare /= static_cast<double>(points.size());
  const double limit2 = fraction * fraction * meanSquare;
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      if ((points[i] - points[j]).squaredNorm() <= limit2) return {static_cast<int>(i), static_cast<int>(j)};
  return {-1, -1};
}

}  // namespace

const char* RegistrationModeName(RegistrationMode mode) {
  return mode == RegistrationMode::Similarity ? "similarity" : "rigid";
}

Eigen::Matrix4d SimilarityTransform::Matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = this->Scale * this->Rotation;
  m.topRightCorner<3, 1>() = this->Translation;
  return m;
}

SimilarityTransform SimilarityTransform::Inverse() const {
  SimilarityTransform inverse;
  inverse.Rotation = this->Rotation.transpose();
  inverse.Scale = 1.0 / this->Scale;
  inverse.Translation = -inverse.Scale * (inverse.Rotation * this->Translation);
  return inverse;
}

SimilarityTransform SimilarityTransform::Compose(const SimilarityTransform& other) const {
  SimilarityTransform result;
  result.Rotation = this->Rotation * other.Rotation;
  result.Scale = this->Scale * other.Scale;
  result.Translation = this->Apply(other.Translation);
  return result;
}

bool SolvePairedPoints(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                       RegistrationMode mode, SimilarityTransform& result) {
  double totalWeight = 0;
  Eigen::Vector3d fromCentroid = Eigen::Vector3d::Zero(), toCentroid = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? weights[i] : 1.0;
    totalWeight += w;
    fromCentroid += w * from[i];
    toCentroid += w * to[i];
  }
  if (!(totalWeight > 0)) return false;
  fromCentroid /= totalWeight;
  toCentroid /= totalWeight;
  // Cross-covariance of the centred sets (two passes: no cancellation far from the origin).
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  double fromSpread = 0;
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? weights[i] : 1.0;
    const Eigen::Vector3d p = from[i] - fromCentroid;
    h.noalias() += (w * p) * (to[i] - toCentroid).transpose();
    fromSpread += w * p.squaredNorm();
  }
  if (!(fromSpread > 0)) return false;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  // The determinant correction: when V·Uᵀ is a reflection, flip the axis of the smallest
  // singular value, which gives the best proper rotation (Umeyama 1991).
  Eigen::Vector3d d(1.0, 1.0, (v * u.transpose()).determinant() < 0 ? -1.0 : 1.0);
  result.Rotation = v * d.asDiagonal() * u.transpose();
  result.Scale = mode == RegistrationMode::Similarity ? svd.singularValues().dot(d) / fromSpread : 1.0;
  result.Translation = toCentroid - result.Scale * (result.Rotation * fromCentroid);
  return true;
}

Eigen::Vector3d CentredSingularValues(const PointList& points) {
  if (points.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) scatter.noalias() += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter, Eigen::EigenvaluesOnly);
  Eigen::Vector3d s = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  return Eigen::Vector3d(s[2], s[1], s[0]);
}

double RotationDifferenceDegrees(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  // ‖A − B‖_F = 2√2·sin(θ/2): accurate for tiny angles, unlike acos((trace − 1)/2).
  const double x = std::min(1.0, (a - b).norm() / (2.0 * std::sqrt(2.0)));
  return 2.0 * std::asin(x) * 180.0 / M_PI;
}

PairedPointResult RegisterPairedPoints(const PointList& from, const PointList& to, const PairedPointOptions& options) {
  PairedPointResult result;
  const size_t n = from.size();
  if (from.size() != to.size()) {
    result.Error = "unequal numbers of points: " + std::to_string(from.size()) + " 'from' and " +
                   std::to_string(to.size()) + " 'to' (every landmark needs its pair)";
    return result;
  }
  if (n < 3) {
    result.Error = "fewer than 3 point pairs (" + std::to_string(n) + "): a rigid registration needs at least 3";
    return result;
  }
  if (!AllFinite(from) || !AllFinite(to)) {
    result.Error = "a point has a non-finite coordinate (NaN or infinity)";
    return result;
  }
  const double* weights = nullptr;
  if (!options.Weights.empty()) {
    if (options.Weights.size() != n) {
      result.Error = "there are " + std::to_string(options.Weights.size()) + " weights for " + std::to_string(n) +
                     " point pairs";
      return result;
    }
    size_t positive = 0;
    for (double w : options.Weights) {
      if (!std::isfinite(w) || w < 0) {
        result.Error = "weights must be finite and non-negative";
        return result;
      }
      positive += (w > 0);
    }
    if (positive < 3) {
      result.Error = "fewer than 3 point pairs have a positive weight";
      return result;
    }
    weights = options.Weights.data();
  }
  for (const auto* set : {&from, &to}) {
    const char* name = set == &from ? "'from'" : "'to'";
    const auto [i, j] = FindCoincident(*set, options.CoincidentFraction);
    if (i >= 0) {
      result.Error = std::string("points ") + std::to_string(i + 1) + " and " + std::to_string(j + 1) + " of the " +
                     name + " set coincide (picked twice?)";
      return result;
    }
    const Eigen::Vector3d s = CentredSingularValues(*set);
    const double ratio = s[0] > 0 ? s[1] / s[0] : 0.0;
    result.SpreadRatio = set == &from ? ratio : std::min(result.SpreadRatio, ratio);
    if (ratio < options.MinimumSpreadRatio) {
      result.Error = std::string("the ") + name + " points are " + (ratio < 1e-9 ? "collinear" : "nearly collinear") +
                     Format(" (spread ratio s2/s1 = %.3g < %.3g): add a landmark away from their line", ratio,
                            options.MinimumSpreadRatio);
      return result;
    }
  }
  if (!SolvePairedPoints(from.data(), to.data(), weights, n, options.Mode, result.Transform)) {
    result.Error = "the weighted points have no spread";
    return result;
  }
  double sum = 0, totalWeight = 0;
  result.Residuals.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? weights[i] : 1.0;
    result.Residuals[i] = (result.Transform.Apply(from[i]) - to[i]).norm();
    sum += w * result.Residuals[i] * result.Residuals[i];
    totalWeight += w;
  }
  result.FRE = std::sqrt(sum / totalWeight);
  result.Ok = true;
  return result;
}

}  // namespace rp
