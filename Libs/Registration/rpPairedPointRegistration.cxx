#include "rpPairedPointRegistration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <numeric>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "rpFormat.h"

namespace rp {

namespace {

bool AllFinite(const PointList& points) {
  for (const auto& p : points)
    if (!p.allFinite()) return false;
  return true;
}

// First pair of points closer than `fraction` of the set's RMS radius, or {-1,-1}. Sorted by
// x and swept, so it stays cheap for large sets.
std::pair<int, int> FindCoincident(const PointList& points, double fraction) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  double meanSquare = 0;
  for (const auto& p : points) meanSquare += (p - centroid).squaredNorm();
  meanSquare /= static_cast<double>(points.size());
  const double limit = fraction * std::sqrt(meanSquare);
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return points[static_cast<size_t>(a)].x() < points[static_cast<size_t>(b)].x(); });
  std::pair<int, int> found{-1, -1};
  for (size_t i = 0; i < order.size(); ++i) {
    const Eigen::Vector3d& p = points[static_cast<size_t>(order[i])];
    for (size_t j = i + 1; j < order.size(); ++j) {
      const Eigen::Vector3d& q = points[static_cast<size_t>(order[j])];
      if (q.x() - p.x() > limit) break;
      if ((p - q).norm() <= limit) {
        const std::pair<int, int> pair{std::min(order[i], order[j]), std::max(order[i], order[j])};
        if (found.first < 0 || pair < found) found = pair;  // report the lowest indices
      }
    }
  }
  return found;
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

namespace {

// One pass over the pairs, relative to the first pair (so coordinates far from the origin,
// as a tracker's ~1 m, lose nothing to cancellation): weighted centroids, the cross-covariance
// M = Σ w (p − p̄)(q − q̄)ᵀ and the spreads Σ w |p − p̄|², Σ w |q − q̄|².
template <bool Weighted>
bool AccumulateT(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                 Eigen::Vector3d& fromCentroid, Eigen::Vector3d& toCentroid, Eigen::Matrix3d& m, double& fromSpread,
                 double& toSpread) {
  if (n == 0) return false;
  const Eigen::Vector3d p0 = from[0], q0 = to[0];
  double total = 0;
  Eigen::Vector3d sa = Eigen::Vector3d::Zero(), sb = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sab = Eigen::Matrix3d::Zero();
  double saa = 0, sbb = 0;
  for (size_t i = 0; i < n; ++i) {
    const double w = Weighted ? weights[i] : 1.0;
    const Eigen::Vector3d a = from[i] - p0, b = to[i] - q0;
    const Eigen::Vector3d wa = w * a;
    total += w;
    sa += wa;
    sb += w * b;
    sab.noalias() += wa * b.transpose();
    saa += wa.dot(a);
    sbb += w * b.squaredNorm();
  }
  if (!(total > 0)) return false;
  const Eigen::Vector3d ca = sa / total, cb = sb / total;
  m = sab - total * ca * cb.transpose();
  fromSpread = saa - total * ca.squaredNorm();
  toSpread = sbb - total * cb.squaredNorm();
  fromCentroid = p0 + ca;
  toCentroid = q0 + cb;
  return fromSpread > 0;
}

bool Accumulate(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                Eigen::Vector3d& fromCentroid, Eigen::Vector3d& toCentroid, Eigen::Matrix3d& m, double& fromSpread,
                double& toSpread) {
  return weights ? AccumulateT<true>(from, to, weights, n, fromCentroid, toCentroid, m, fromSpread, toSpread)
                 : AccumulateT<false>(from, to, weights, n, fromCentroid, toCentroid, m, fromSpread, toSpread);
}

double Det3(double a, double b, double c, double d, double e, double f, double g, double h, double i) {
  return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
}

constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

// Determinant of `a` without row `row` and column `col`.
inline double Minor(const Eigen::Matrix4d& a, int row, int col) {
  const int* r = kOthers[row];
  const int* c = kOthers[col];
  return Det3(a(r[0], c[0]), a(r[0], c[1]), a(r[0], c[2]), a(r[1], c[0]), a(r[1], c[1]), a(r[1], c[2]),
              a(r[2], c[0]), a(r[2], c[1]), a(r[2], c[2]));
}

// Column J of adj(a) (indices known at compile time: the common case costs four 3x3 minors).
template <int J>
Eigen::Vector4d AdjugateColumn(const Eigen::Matrix4d& a) {
  Eigen::Vector4d v;
  for (int i = 0; i < 4; ++i) v[i] = ((i + J) % 2 ? -1.0 : 1.0) * Minor(a, J, i);
  return v;
}

}  // namespace

bool SolvePairedPoints(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                       RegistrationMode mode, SimilarityTransform& result) {
  Eigen::Vector3d fromCentroid, toCentroid;
  Eigen::Matrix3d m;
  double fromSpread, toSpread;
  if (!Accumulate(from, to, weights, n, fromCentroid, toCentroid, m, fromSpread, toSpread)) return false;
  const double sxx = m(0, 0), sxy = m(0, 1), sxz = m(0, 2), syx = m(1, 0), syy = m(1, 1), syz = m(1, 2),
               szx = m(2, 0), szy = m(2, 1), szz = m(2, 2);
  // Horn's key matrix: its top eigenvector is the quaternion of the best rotation p → q.
  Eigen::Matrix4d k;
  k << sxx + syy + szz, syz - szy, szx - sxz, sxy - syx,  //
      syz - szy, sxx - syy - szz, sxy + syx, szx + sxz,   //
      szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy,  //
      sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz;
  // Characteristic polynomial λ⁴ + c2 λ² + c1 λ + c0 (K is traceless); Newton from the upper
  // bound (|p|² + |q|²)/2 descends monotonically onto the largest root.
  const double c2 = -2.0 * m.squaredNorm();
  const double c1 = -8.0 * m.determinant();
  const double c0 = k.determinant();
  double lambda = 0.5 * (fromSpread + toSpread);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double l2 = lambda * lambda;
    const double p = (l2 + c2) * l2 + c1 * lambda + c0;
    const double dp = 2.0 * (2.0 * l2 + c2) * lambda + c1;
    if (dp == 0) break;
    const double step = p / dp;
    lambda -= step;
    // Quadratic convergence: after a step of 1e-9·λ the remaining error is ~1e-18·λ²/gap.
    if (std::abs(step) <= 1e-9 * std::abs(lambda)) break;
  }
  // The quaternion v spans the null space of A = K − λI, and adj(A) = −P'(λ)·v·vᵀ (the trace of
  // the adjugate is the derivative of the characteristic polynomial). A column j of adj(A) gives
  // v accurately when v_j² = |adj(A)_jj / P'(λ)| is not small: try the first column (w, the
  // usual case), else the column with the largest diagonal cofactor.
  const Eigen::Matrix4d a = k - lambda * Eigen::Matrix4d::Identity();
  const double derivative = std::abs(2.0 * (2.0 * lambda * lambda + c2) * lambda + c1);
  Eigen::Vector4d v = AdjugateColumn<0>(a);
  if (!(std::abs(v[0]) > 0.1 * derivative)) {
    int best = 0;
    double bestCofactor = std::abs(v[0]);
    for (int j = 1; j < 4; ++j) {
      const double cofactor = std::abs(Minor(a, j, j));
      if (cofactor > bestCofactor) {
        bestCofactor = cofactor;
        best = j;
      }
    }
    switch (best) {
      case 1: v = AdjugateColumn<1>(a); break;
      case 2: v = AdjugateColumn<2>(a); break;
      case 3: v = AdjugateColumn<3>(a); break;
      default: break;
    }
  }
  const double norm = v.norm();
  if (!(norm > 0) || !std::isfinite(norm)) {
    // Every cofactor vanished: only for degenerate (collinear) sets. Fall back to the SVD.
    return SolvePairedPointsSVD(from, to, weights, n, mode, result);
  }
  v /= norm;
  result.Rotation = Eigen::Quaterniond(v[0], v[1], v[2], v[3]).toRotationMatrix();
  result.Scale = mode == RegistrationMode::Similarity ? lambda / fromSpread : 1.0;
  result.Translation = toCentroid - result.Scale * (result.Rotation * fromCentroid);
  return true;
}

bool SolvePairedPointsSVD(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
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
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(scatter, Eigen::EigenvaluesOnly);  // closed form: enough for a ratio test
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
