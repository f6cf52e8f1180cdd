#pragma once
// How far to trust a paired-point registration. FRE (eq. 8) only says how well the fiducials
// fit each other; the error that matters is at the target (TRE). From a prior fiducial
// localization error (FLE, RMS over 3D, e.g. 0.25 mm for a Polaris plus the picking error in
// the image, added in quadrature) Fitzpatrick, West & Maurer 1998 predict
//     TRE²(r) ≈ FLE²/N · (1 + 1/3 · Σ_k d_k²/f_k²)
// (d_k: distance of the target from principal axis k of the fiducial configuration, f_k: RMS
// distance of the fiducials from that axis), and the expected FRE² ≈ (1 − 2/N)·FLE².
// The formulas are for rigid registration with equal weights and isotropic FLE (with weights or
// in similarity mode they are an approximation). Leave-one-out residuals find a mislocalized or
// swapped fiducial.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rpPairedPointRegistration.h"

namespace rp {

class TREPredictor {
 public:
  /// `fiducials`: the configuration in the space targets are given in; `fle`: RMS FLE in mm.
  TREPredictor(const PointList& fiducials, double fle);
  /// Predicted RMS TRE at `target` (mm); NaN with fewer than 3 fiducials or a collinear set.
  double PredictRMS(const Eigen::Vector3d& target) const;
  /// TRE / FLE at `target` (the geometric factor, independent of FLE).
  double RelativeRMS(const Eigen::Vector3d& target) const;
  /// Expected FRE (RMS over the fiducials) for this N and FLE: FLE·sqrt(1 − 2/N).
  double ExpectedFRE() const;
  int NumberOfFiducials() const { return this->N; }
  double FLE() const { return this->Fle; }
  const Eigen::Vector3d& Centroid() const { return this->Center; }

 private:
  int N = 0;
  double Fle = 0;
  Eigen::Vector3d Center = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Axes = Eigen::Matrix3d::Identity();  // columns: principal axes
  Eigen::Vector3d AxisRMS2 = Eigen::Vector3d::Zero();  // f_k²
};

/// Residual of each pair under the registration of all the other pairs: |T₋ᵢ(fromᵢ) − toᵢ|.
/// NaN where fewer than 3 pairs remain or the remaining set cannot be solved.
std::vector<double> LeaveOneOutResiduals(const PointList& from, const PointList& to, RegistrationMode mode,
                                         const std::vector<double>& weights = {});

struct SuspectFiducial {
  int Index = -1;
  double LeaveOneOut = 0;  // mm, in the round it was found
  double Expected = 0;     // mm, RMS expected from FLE and the geometry
  std::string Reason;
};

/// Sequential leave-one-out test: takes the pair whose removal leaves the best-fitting set,
/// flags it when its leave-one-out residual exceeds `factor` times what FLE predicts for it
/// (sqrt(FLE² + TRE²₋ᵢ(toᵢ))), removes it and repeats while at least 4 pairs remain. With fle ≤ 0 the FLE is
/// estimated from the FRE of the remaining pairs. A swapped pair is flagged as two
/// points, one round each.
std::vector<SuspectFiducial> FindSuspectFiducials(const PointList& from, const PointList& to, RegistrationMode mode,
                                                  double fle, double factor = 3.0);

struct AssessmentOptions {
  PairedPointOptions Registration;
  double FREThreshold = 0;  // mm; ≤ 0: no threshold
  double FLE = 0;           // prior RMS FLE, mm; ≤ 0: unknown (no TRE prediction, no FRE warning)
  double FREWarningFactor = 2.0;  // warn when FRE > factor · expected FRE
  double SuspectFactor = 3.0;     // leave-one-out flag (see FindSuspectFiducials)
  std::optional<Eigen::Vector3d> Target;  // in the 'to' space
};

struct RegistrationAssessment {
  PairedPointResult Solution;
  bool Accepted = false;
  std::string Reason;  // why accepted or rejected, with the numbers
  std::vector<std::string> Warnings;
  std::vector<double> LeaveOneOut;
  std::vector<SuspectFiducial> Suspects;
  double ExpectedFRE = std::numeric_limits<double>::quiet_NaN();
  double PredictedTREAtTarget = std::numeric_limits<double>::quiet_NaN();
  double PredictedTREAtCentroid = std::numeric_limits<double>::quiet_NaN();
  double MaxPredictedTREAtFiducials = std::numeric_limits<double>::quiet_NaN();
};

/// Registers, then accepts or rejects against the FRE threshold (seed 3.2.2) and adds what the
/// user needs to judge the result: predicted TRE, leave-one-out residuals, suspects, warnings.
RegistrationAssessment AssessRegistration(const PointList& from, const PointList& to, const AssessmentOptions& options);

}  // namespace rp
