#include "rpRegistrationAccuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Eigenvalues>

#include "rpFormat.h"

namespace rp {

TREPredictor::TREPredictor(const PointList& fiducials, double fle) : N(static_cast<int>(fiducials.size())), Fle(fle) {
  if (fiducials.empty()) return;
  for (const auto& p : fiducials) this->Center += p;
  this->Center /= static_cast<double>(this->N);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : fiducials) covariance.noalias() += (p - this->Center) * (p - this->Center).transpose();
  covariance /= static_cast<double>(this->N);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  this->Axes = eigen.eigenvectors();
  const Eigen::Vector3d lambda = eigen.eigenvalues().cwiseMax(0.0);
  // Mean squared distance of the fiducials from axis k = sum of the variances along the others.
  const double total = lambda.sum();
  for (int k = 0; k < 3; ++k) this->AxisRMS2[k] = total - lambda[k];
}

double TREPredictor::RelativeRMS(const Eigen::Vector3d& target) const {
  if (this->N < 3) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d r = target - this->Center;
  const double r2 = r.squaredNorm();
  double sum = 0;
  for (int k = 0; k < 3; ++k) {
    if (!(this->AxisRMS2[k] > 0)) return std::numeric_limits<double>::quiet_NaN();  // collinear
    const double along = r.dot(this->Axes.col(k));
    sum += std::max(0.0, r2 - along * along) / this->AxisRMS2[k];
  }
  return std::sqrt((1.0 + sum / 3.0) / this->N);
}

double TREPredictor::PredictRMS(const Eigen::Vector3d& target) const { return this->Fle * this->RelativeRMS(target); }

double TREPredictor::ExpectedFRE() const {
  if (this->N < 3) return std::numeric_limits<double>::quiet_NaN();
  return this->Fle * std::sqrt(1.0 - 2.0 / this->N);
}

std::vector<double> LeaveOneOutResiduals(const PointList& from, const PointList& to, RegistrationMode mode,
                                         const std::vector<double>& weights) {
  const size_t n = std::min(from.size(), to.size());
  std::vector<double> residuals(n, std::numeric_limits<double>::quiet_NaN());
  if (n < 4) return residuals;
  PointList subFrom(n - 1), subTo(n - 1);
  std::vector<double> subWeights(weights.size() == n ? n - 1 : 0);
  for (size_t i = 0; i < n; ++i) {
    size_t m = 0;
    for (size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      subFrom[m] = from[j];
      subTo[m] = to[j];
      if (!subWeights.empty()) subWeights[m] = weights[j];
      ++m;
    }
    SimilarityTransform t;
    if (SolvePairedPoints(subFrom.data(), subTo.data(), subWeights.empty() ? nullptr : subWeights.data(), n - 1, mode,
                          t)) {
      residuals[i] = (t.Apply(from[i]) - to[i]).norm();
    }
  }
  return residuals;
}

std::vector<SuspectFiducial> FindSuspectFiducials(const PointList& from, const PointList& to, RegistrationMode mode,
                                                  double fle, double factor) {
  std::vector<SuspectFiducial> suspects;
  std::vector<int> active;
  for (int i = 0; i < static_cast<int>(std::min(from.size(), to.size())); ++i) active.push_back(i);
  while (active.size() >= 4) {
    const size_t n = active.size();
    std::vector<double> loo(n, 0.0), relative(n, 1.0), remainingCost(n, 0.0);
    std::vector<bool> valid(n, false);
    PointList subFrom(n - 1), subTo(n - 1);
    for (size_t a = 0; a < n; ++a) {
      size_t m = 0;
      for (size_t b = 0; b < n; ++b) {
        if (b == a) continue;
        subFrom[m] = from[static_cast<size_t>(active[b])];
        subTo[m] = to[static_cast<size_t>(active[b])];
        ++m;
      }
      SimilarityTransform t;
      if (!SolvePairedPoints(subFrom.data(), subTo.data(), nullptr, n - 1, mode, t)) continue;
      const Eigen::Vector3d& target = to[static_cast<size_t>(active[a])];
      const double g = TREPredictor(subTo, 1.0).RelativeRMS(target);
      if (!std::isfinite(g)) continue;
      loo[a] = (t.Apply(from[static_cast<size_t>(active[a])]) - target).norm();
      relative[a] = std::sqrt(1.0 + g * g);  // expected residual / FLE: the point's own FLE + TRE₋ᵢ
      for (size_t k = 0; k + 1 < n; ++k) remainingCost[a] += (t.Apply(subFrom[k]) - subTo[k]).squaredNorm();
      valid[a] = true;
    }
    // The candidate is the pair whose removal leaves the best-fitting set (with a swapped pair,
    // the largest leave-one-out residual can belong to a good point dragged by the bad ones).
    size_t worst = n;
    for (size_t a = 0; a < n; ++a) {
      if (valid[a] && (worst == n || remainingCost[a] < remainingCost[worst])) worst = a;
    }
    if (worst == n) break;
    double fleUsed = fle;
    if (!(fleUsed > 0)) {
      // No prior: FLE from the FRE of the remaining set, FLE² ≈ FRE²/(1 − 2/M) (M = n − 1 pairs).
      // Choosing the best-fitting subset biases this low, so flags come a little more easily.
      const double m = static_cast<double>(n - 1);
      fleUsed = std::sqrt(remainingCost[worst] / m / (1.0 - 2.0 / m));
      if (!(fleUsed > 0)) break;  // an exact fit: nothing to compare with
    }
    const double worstRatio = loo[worst] / (fleUsed * relative[worst]);
    if (worst == n || worstRatio <= factor) break;
    SuspectFiducial s;
    s.Index = active[worst];
    s.LeaveOneOut = loo[worst];
    s.Expected = fleUsed * relative[worst];
    s.Reason = Format("leave-one-out residual %.3g mm is %.3g times the %.3g mm expected (FLE %.3g mm", s.LeaveOneOut,
                      worstRatio, s.Expected, fleUsed) +
               (fle > 0 ? "" : ", estimated") + "): mislocalized, or swapped with another point";
    suspects.push_back(s);
    active.erase(active.begin() + static_cast<long>(worst));
  }
  return suspects;
}

RegistrationAssessment AssessRegistration(const PointList& from, const PointList& to,
                                          const AssessmentOptions& options) {
  RegistrationAssessment a;
  a.Solution = RegisterPairedPoints(from, to, options.Registration);
  if (!a.Solution.Ok) {
    a.Accepted = false;
    a.Reason = "refused: " + a.Solution.Error;
    return a;
  }
  const RegistrationMode mode = options.Registration.Mode;
  const int n = static_cast<int>(from.size());
  a.LeaveOneOut = LeaveOneOutResiduals(from, to, mode, options.Registration.Weights);
  if (options.FLE > 0) {
    const TREPredictor predictor(to, options.FLE);
    a.ExpectedFRE = predictor.ExpectedFRE();
    a.PredictedTREAtCentroid = predictor.PredictRMS(predictor.Centroid());
    a.MaxPredictedTREAtFiducials = 0;
    for (const auto& q : to) a.MaxPredictedTREAtFiducials = std::max(a.MaxPredictedTREAtFiducials, predictor.PredictRMS(q));
    if (options.Target) a.PredictedTREAtTarget = predictor.PredictRMS(*options.Target);
    if (a.Solution.FRE > options.FREWarningFactor * a.ExpectedFRE) {
      a.Warnings.push_back(Format("FRE %.3g mm is %.3g times the %.3g mm expected from FLE %.3g mm", a.Solution.FRE,
                                  a.Solution.FRE / a.ExpectedFRE, a.ExpectedFRE, options.FLE) +
                           " with " + std::to_string(n) +
                           " fiducials: check for a mislocalized or swapped fiducial, a mirrored (left/right) point "
                           "set, or a larger FLE than assumed");
    }
  }
  if (n >= 4) {
    a.Suspects = FindSuspectFiducials(from, to, mode, options.FLE, options.SuspectFactor);
    for (const auto& s : a.Suspects) {
      a.Warnings.push_back("fiducial " + std::to_string(s.Index + 1) + ": " + s.Reason);
    }
  }
  if (options.FREThreshold > 0 && a.Solution.FRE > options.FREThreshold) {
    a.Accepted = false;
    a.Reason = Format("rejected: FRE %.3f mm exceeds the threshold %.3f mm", a.Solution.FRE, options.FREThreshold);
  } else {
    a.Accepted = true;
    a.Reason = options.FREThreshold > 0
                   ? Format("accepted: FRE %.3f mm is within the threshold %.3f mm", a.Solution.FRE, options.FREThreshold)
                   : Format("accepted: FRE %.3f mm (no threshold set)", a.Solution.FRE);
  }
  return a;
}

}  // namespace rp
