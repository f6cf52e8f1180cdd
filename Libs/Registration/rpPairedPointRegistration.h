#pragma once
// Paired-point registration (seed eq. 7): the rigid (or similarity) transform that maps "from"
// points (e.g. landmarks digitized with a tracked stylus) onto "to" points (the same landmarks
// picked in the image), by least squares (Horn 1987's unit quaternion, so the result is always a
// proper rotation, never a reflection; equal to Umeyama 1991's SVD with the determinant
// correction). Double precision,
// optional per-pair weights. Degenerate inputs are refused with a message that says what to fix.
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rp {

using PointList = std::vector<Eigen::Vector3d>;

enum class RegistrationMode { Rigid, Similarity };

const char* RegistrationModeName(RegistrationMode mode);

/// y = Scale · Rotation · x + Translation (Scale is 1 in rigid mode).
struct SimilarityTransform {
  Eigen::Matrix3d Rotation = Eigen::Matrix3d::Identity();
  double Scale = 1.0;
  Eigen::Vector3d Translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d Apply(const Eigen::Vector3d& x) const { return this->Scale * (this->Rotation * x) + this->Translation; }
  Eigen::Matrix4d Matrix() const;
  SimilarityTransform Inverse() const;
  /// this ∘ other (other applied first).
  SimilarityTransform Compose(const SimilarityTransform& other) const;
};

struct PairedPointOptions {
  RegistrationMode Mode = RegistrationMode::Rigid;
  /// Empty: every pair weighs 1. Otherwise one non-negative weight per pair (e.g. 1/FLE_i²);
  /// at least 3 pairs must have a positive weight.
  std::vector<double> Weights;
  /// Near-collinear test, unitless: the second singular value of the centred points over the
  /// first (s2/s1, the ratio of the spreads across and along the best line). Below this the
  /// rotation about that line is undetermined and the set is refused.
  double MinimumSpreadRatio = 0.05;
  /// Two points of one set closer than this fraction of the set's RMS radius are "coincident".
  double CoincidentFraction = 1e-3;
};

struct PairedPointResult {
  bool Ok = false;
  std::string Error;  // why the input was refused (empty when Ok)
  SimilarityTransform Transform;
  double FRE = std::numeric_limits<double>::quiet_NaN();  // eq. 8 (weighted RMS when weighted)
  std::vector<double> Residuals;                          // |T(from_i) - to_i| per pair, mm
  double SpreadRatio = 0;                                 // min over both sets of s2/s1
};

/// Validates the pairs, then solves. Never throws; Ok=false with Error on degenerate input.
PairedPointResult RegisterPairedPoints(const PointList& from, const PointList& to,
                                       const PairedPointOptions& options = {});

/// The solver alone, without validation (for leave-one-out, ICP and benchmarks): n pairs,
/// weights may be null. Returns false only when the weighted spread of `from` is zero.
/// Horn's quaternion formulation solved as in QCP (Theobald 2005): the largest eigenvalue of
/// the 4x4 key matrix by Newton's method on its characteristic polynomial, the quaternion from
/// the adjugate of (K − λI). A unit quaternion is always a proper rotation, and the largest
/// eigenvalue is σ1 + σ2 + sign(det)·σ3, exactly Umeyama's reflection-corrected optimum.
bool SolvePairedPoints(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                       RegistrationMode mode, SimilarityTransform& result);

/// The textbook solver (Arun/Umeyama: 3x3 SVD with the determinant correction), kept as the
/// reference the fast one is tested against.
bool SolvePairedPointsSVD(const Eigen::Vector3d* from, const Eigen::Vector3d* to, const double* weights, size_t n,
                          RegistrationMode mode, SimilarityTransform& result);

/// Singular values (descending) of the centred points, i.e. the RMS spreads along the principal
/// axes times sqrt(n).
Eigen::Vector3d CentredSingularValues(const PointList& points);

/// Angle of the rotation R_a · R_bᵀ in degrees (0 when equal).
double RotationDifferenceDegrees(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace rp
