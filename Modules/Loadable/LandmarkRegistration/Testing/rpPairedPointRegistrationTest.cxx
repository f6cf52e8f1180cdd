// Paired-point registration with known answers: exact recovery, reflections, refusals, Monte
// Carlo against the Fitzpatrick-West-Maurer predictions, leave-one-out, handedness, ICP.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkDataArray.h>

#include "rpPairedPointRegistration.h"
#include "rpRegistrationAccuracy.h"
#include "rpSurfaceICP.h"
#include "rpTREMap.h"

namespace {

using rp::PointList;
using rp::RegistrationMode;
using rp::SimilarityTransform;

Eigen::Matrix3d RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return q.normalized().toRotationMatrix();
}

PointList RandomPoints(std::mt19937& rng, int n, double radius) {
  std::uniform_real_distribution<double> u(-radius, radius);
  PointList points;
  while (static_cast<int>(points.size()) < n) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (p.norm() <= radius) points.push_back(p);
  }
  return points;
}

PointList Apply(const SimilarityTransform& t, const PointList& points) {
  PointList out;
  for (const auto& p : points) out.push_back(t.Apply(p));
  return out;
}

SimilarityTransform RandomTransform(std::mt19937& rng, bool withScale) {
  std::uniform_real_distribution<double> shift(-300, 300), scale(0.5, 2.0);
  SimilarityTransform t;
  t.Rotation = RandomRotation(rng);
  t.Translation = Eigen::Vector3d(shift(rng), shift(rng), shift(rng));
  t.Scale = withScale ? scale(rng) : 1.0;
  return t;
}

TEST(PairedPoint, ExactRecoveryOfRandomRigidAndSimilarityTransforms) {
  std::mt19937 rng(1);
  for (bool similarity : {false, true}) {
    for (int n : {3, 4, 6, 10, 50, 100}) {
      for (int trial = 0; trial < 20; ++trial) {
        const SimilarityTransform truth = RandomTransform(rng, similarity);
        const PointList from = RandomPoints(rng, n, 80);
        const PointList to = Apply(truth, from);
        rp::PairedPointOptions options;
        options.Mode = similarity ? RegistrationMode::Similarity : RegistrationMode::Rigid;
        const auto result = rp::RegisterPairedPoints(from, to, options);
        ASSERT_TRUE(result.Ok) << result.Error;
        EXPECT_LT((result.Transform.Rotation - truth.Rotation).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_NEAR(result.Transform.Scale, truth.Scale, 1e-9);
        EXPECT_LT((result.Transform.Translation - truth.Translation).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_NEAR(result.Transform.Rotation.determinant(), 1.0, 1e-12);
        EXPECT_LT(result.FRE, 1e-9);
        ASSERT_EQ(result.Residuals.size(), static_cast<size_t>(n));
      }
    }
  }
}

TEST(PairedPoint, QuaternionSolverMatchesTheSVDReference) {
  // Noisy, mirrored, planar and weighted problems: the fast solver gives Umeyama's answer.
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 2.0);
  std::uniform_real_distribution<double> weight(0.1, 3.0);
  double worstAngle = 0, worstShift = 0, worstScale = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 3 + trial % 20;
    PointList from;
    do {  // sets the registration accepts (not nearly collinear), some of them planar
      from = RandomPoints(rng, n, 70);
      if (trial % 7 == 0)
        for (auto& p : from) p.z() = 0;
    } while (rp::CentredSingularValues(from)[1] < 0.05 * rp::CentredSingularValues(from)[0]);
    SimilarityTransform truth = RandomTransform(rng, trial % 2 == 1);
    if (trial % 11 == 0)  // half turns: the quaternion's w is 0, its first adjugate column vanishes
      truth.Rotation = Eigen::AngleAxisd(M_PI, RandomRotation(rng).col(0)).toRotationMatrix();
    PointList to = Apply(truth, from);
    if (trial % 13 != 0)  // and some exact problems
      for (auto& q : to) q += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    if (trial % 5 == 0)
      for (auto& q : to) q.x() = -q.x();  // a reflection to be corrected
    std::vector<double> w;
    if (trial % 3 == 0)
      for (int i = 0; i < n; ++i) w.push_back(weight(rng));
    const RegistrationMode mode = trial % 2 ? RegistrationMode::Similarity : RegistrationMode::Rigid;
    SimilarityTransform fast, reference;
    ASSERT_TRUE(rp::SolvePairedPoints(from.data(), to.data(), w.empty() ? nullptr : w.data(), from.size(), mode, fast));
    ASSERT_TRUE(
        rp::SolvePairedPointsSVD(from.data(), to.data(), w.empty() ? nullptr : w.data(), from.size(), mode, reference));
    EXPECT_NEAR(fast.Rotation.determinant(), 1.0, 1e-12);
    worstAngle = std::max(worstAngle, rp::RotationDifferenceDegrees(fast.Rotation, reference.Rotation));
    worstShift = std::max(worstShift, (fast.Translation - reference.Translation).norm());
    worstScale = std::max(worstScale, std::abs(fast.Scale - reference.Scale));
  }
  EXPECT_LT(worstAngle, 1e-8);
  EXPECT_LT(worstShift, 1e-7);
  EXPECT_LT(worstScale, 1e-10);
}

TEST(PairedPoint, WeightsSelectThePairsThatCount) {
  std::mt19937 rng(2);
  const SimilarityTransform truth = RandomTransform(rng, false);
  const PointList from = RandomPoints(rng, 6, 60);
  PointList to = Apply(truth, from);
  to[2] += Eigen::Vector3d(15, -10, 5);  // a wrong pair, weighted out
  rp::PairedPointOptions options;
  options.Weights = {1, 2, 0, 0.5, 1, 3};
  const auto result = rp::RegisterPairedPoints(from, to, options);
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_LT((result.Transform.Rotation - truth.Rotation).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((result.Transform.Translation - truth.Translation).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(result.Residuals[2], Eigen::Vector3d(15, -10, 5).norm(), 1e-9);
  EXPECT_LT(result.FRE, 1e-9);  // weighted FRE: the zero-weight pair does not count
}

TEST(PairedPoint, PlanarSetsGiveARotationNotAReflection) {
  // Coplanar points (always the case for 3): the cross-covariance has a zero singular value and
  // a reflection fits exactly as well; the determinant correction must pick the rotation.
  std::mt19937 rng(3);
  for (int n : {3, 4, 8}) {
    for (int trial = 0; trial < 50; ++trial) {
      PointList from;
      do {  // a planar set, not close to a line
        from = RandomPoints(rng, n, 50);
        for (auto& p : from) p.z() = 0;
      } while (rp::CentredSingularValues(from)[1] < 0.2 * rp::CentredSingularValues(from)[0]);
      const SimilarityTransform truth = RandomTransform(rng, false);
      const auto result = rp::RegisterPairedPoints(from, Apply(truth, from));
      ASSERT_TRUE(result.Ok) << result.Error;
      EXPECT_NEAR(result.Transform.Rotation.determinant(), 1.0, 1e-12);
      EXPECT_LT((result.Transform.Rotation - truth.Rotation).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

double CentredCost(const PointList& from, const PointList& to, const Eigen::Matrix3d& r) {
  Eigen::Vector3d cf = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < from.size(); ++i) {
    cf += from[i];
    ct += to[i];
  }
  cf /= static_cast<double>(from.size());
  ct /= static_cast<double>(from.size());
  double cost = 0;
  for (size_t i = 0; i < from.size(); ++i) cost += (r * (from[i] - cf) - (to[i] - ct)).squaredNorm();
  return cost;
}

TEST(PairedPoint, MirroredSetGivesTheBestProperRotation) {
  // A left-handed copy (x negated) cannot be reached by a rotation: the result must still be a
  // rotation, and no nearby rotation fits better (it is the constrained optimum).
  std::mt19937 rng(4);
  const PointList from = RandomPoints(rng, 8, 60);
  PointList to;
  for (const auto& p : from) to.emplace_back(-p.x(), p.y(), p.z());
  const auto result = rp::RegisterPairedPoints(from, to);
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_NEAR(result.Transform.Rotation.determinant(), 1.0, 1e-12);
  EXPECT_GT(result.FRE, 5.0);
  const double best = CentredCost(from, to, result.Transform.Rotation);
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Matrix3d nudge = Eigen::AngleAxisd(1e-3, axis).toRotationMatrix();
    EXPECT_GE(CentredCost(from, to, nudge * result.Transform.Rotation), best);
  }
}

TEST(PairedPoint, RefusesDegenerateInput) {
  std::mt19937 rng(5);
  const PointList good = RandomPoints(rng, 5, 50);
  auto refuse = [](const PointList& from, const PointList& to, const std::string& expected,
                   const rp::PairedPointOptions& options = {}) {
    const auto result = rp::RegisterPairedPoints(from, to, options);
    EXPECT_FALSE(result.Ok) << expected;
    EXPECT_NE(result.Error.find(expected), std::string::npos) << "got: " << result.Error;
  };
  refuse({good[0], good[1]}, {good[0], good[1]}, "fewer than 3");
  refuse(good, PointList(good.begin(), good.end() - 1), "unequal numbers");
  PointList twice = good;
  twice[3] = twice[1];
  refuse(twice, good, "points 2 and 4 of the 'from' set coincide");
  refuse(good, twice, "of the 'to' set coincide");
  PointList line;
  for (int i = 0; i < 5; ++i) line.emplace_back(10.0 * i, 5.0 * i, -3.0 * i);
  refuse(line, line, "collinear");
  // Nearly collinear: 200 mm long, 2 mm off the line (s2/s1 ≈ 0.01), far from any mm² threshold.
  PointList nearLine = {{0, 0, 0}, {50, 0, 2}, {100, 0, 0}, {150, 0, -2}, {200, 0, 0}};
  refuse(nearLine, nearLine, "nearly collinear");
  // The same shape at 1/1000 the size is refused for the same reason: the test is unitless.
  PointList tiny;
  for (const auto& p : nearLine) tiny.push_back(p / 1000.0);
  refuse(tiny, tiny, "nearly collinear");
  PointList nan = good;
  nan[0].x() = std::nan("");
  refuse(nan, good, "non-finite");
  rp::PairedPointOptions weights;
  weights.Weights = {1, 1, 0, 0, 0};
  refuse(good, good, "fewer than 3 point pairs have a positive weight", weights);
  weights.Weights = {1, 1, 1};
  refuse(good, good, "3 weights for 5", weights);
  weights.Weights = {1, 1, -1, 1, 1};
  refuse(good, good, "non-negative", weights);

  // Well spread sets are accepted, including a 20 mm-thin slab (ratio well above the limit).
  PointList slab = {{0, 0, 0}, {100, 0, 0}, {0, 20, 0}, {100, 20, 5}};
  EXPECT_TRUE(rp::RegisterPairedPoints(slab, slab).Ok);
}

TEST(PairedPoint, TREPredictorClosedForm) {
  // Six fiducials at ±a on the axes: f_k² = 2a²/3, and at distance d along x
  // TRE² = FLE²/6 · (1 + d²/a²).
  const double a = 40, fle = 0.3;
  const PointList f = {{a, 0, 0}, {-a, 0, 0}, {0, a, 0}, {0, -a, 0}, {0, 0, a}, {0, 0, -a}};
  const rp::TREPredictor predictor(f, fle);
  for (double d : {0.0, 20.0, 40.0, 120.0}) {
    EXPECT_NEAR(predictor.PredictRMS(Eigen::Vector3d(d, 0, 0)), fle * std::sqrt((1 + d * d / (a * a)) / 6), 1e-12);
  }
  EXPECT_NEAR(predictor.ExpectedFRE(), fle * std::sqrt(1 - 2.0 / 6), 1e-12);
}

// Monte Carlo: isotropic Gaussian FLE on the 'to' points, fixed seed.
struct MonteCarlo {
  double MeanFRE2 = 0;
  std::vector<double> RMSTRE;
};

MonteCarlo Simulate(const PointList& fiducials, const std::vector<Eigen::Vector3d>& targets, double fle, int trials,
                    std::mt19937& rng) {
  std::normal_distribution<double> noise(0, fle / std::sqrt(3.0));
  MonteCarlo mc;
  mc.RMSTRE.assign(targets.size(), 0);
  const SimilarityTransform truth = RandomTransform(rng, false);
  const PointList from = Apply(truth.Inverse(), fiducials);
  for (int t = 0; t < trials; ++t) {
    PointList to = fiducials;
    for (auto& p : to) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const auto result = rp::RegisterPairedPoints(from, to);
    EXPECT_TRUE(result.Ok);
    mc.MeanFRE2 += result.FRE * result.FRE;
    const SimilarityTransform error = result.Transform.Compose(truth.Inverse());
    for (size_t k = 0; k < targets.size(); ++k) mc.RMSTRE[k] += (error.Apply(targets[k]) - targets[k]).squaredNorm();
  }
  mc.MeanFRE2 /= trials;
  for (auto& v : mc.RMSTRE) v = std::sqrt(v / trials);
  return mc;
}

TEST(PairedPoint, MonteCarloMatchesFitzpatrickWestMaurer) {
  std::mt19937 rng(2024);
  const double fle = 0.5;
  const int trials = 4000;
  for (int n : {4, 6, 10}) {
    const PointList fiducials = RandomPoints(rng, n, 60);
    const rp::TREPredictor predictor(fiducials, fle);
    const Eigen::Vector3d c = predictor.Centroid();
    const std::vector<Eigen::Vector3d> targets = {c, c + Eigen::Vector3d(40, 0, 0), c + Eigen::Vector3d(0, -70, 30),
                                                  c + Eigen::Vector3d(100, 100, -100), fiducials[0]};
    const MonteCarlo mc = Simulate(fiducials, targets, fle, trials, rng);
    const double expectedFRE2 = (1 - 2.0 / n) * fle * fle;
    EXPECT_NEAR(mc.MeanFRE2 / expectedFRE2, 1.0, 0.05) << "N=" << n;
    EXPECT_NEAR(predictor.ExpectedFRE(), std::sqrt(expectedFRE2), 1e-12);
    for (size_t k = 0; k < targets.size(); ++k) {
      const double predicted = predictor.PredictRMS(targets[k]);
      EXPECT_NEAR(mc.RMSTRE[k] / predicted, 1.0, 0.10) << "N=" << n << " target " << k << " measured "
                                                       << mc.RMSTRE[k] << " predicted " << predicted;
    }
  }
}

TEST(PairedPoint, LeaveOneOutFlagsAnOutlierAndASwappedPair) {
  std::mt19937 rng(6);
  const double fle = 0.25;
  std::normal_distribution<double> noise(0, fle / std::sqrt(3.0));
  int cleanFlags = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const PointList truthTo = RandomPoints(rng, 8, 70);
    const SimilarityTransform truth = RandomTransform(rng, false);
    const PointList from = Apply(truth.Inverse(), truthTo);
    PointList to = truthTo;
    for (auto& p : to) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    cleanFlags += static_cast<int>(rp::FindSuspectFiducials(from, to, RegistrationMode::Rigid, fle).size());

    // One mislocalized point (5 mm off).
    PointList outlier = to;
    outlier[3] += Eigen::Vector3d(3, -4, 0);
    for (double prior : {fle, 0.0}) {  // with the FLE prior, and with FLE estimated
      const auto suspects = rp::FindSuspectFiducials(from, outlier, RegistrationMode::Rigid, prior);
      ASSERT_EQ(suspects.size(), 1u) << "trial " << trial << " prior " << prior;
      EXPECT_EQ(suspects[0].Index, 3);
    }
    const auto loo = rp::LeaveOneOutResiduals(from, outlier, RegistrationMode::Rigid);
    EXPECT_EQ(std::max_element(loo.begin(), loo.end()) - loo.begin(), 3);

    // Two points swapped (labels exchanged).
    PointList swapped = to;
    std::swap(swapped[1], swapped[5]);
    const auto suspects = rp::FindSuspectFiducials(from, swapped, RegistrationMode::Rigid, fle);
    ASSERT_EQ(suspects.size(), 2u) << "trial " << trial;
    EXPECT_EQ(std::min(suspects[0].Index, suspects[1].Index), 1);
    EXPECT_EQ(std::max(suspects[0].Index, suspects[1].Index), 5);
  }
  EXPECT_EQ(cleanFlags, 0);
}

TEST(PairedPoint, AssessmentAcceptsRejectsAndWarns) {
  std::mt19937 rng(7);
  const PointList to = RandomPoints(rng, 6, 60);
  const SimilarityTransform truth = RandomTransform(rng, false);
  const PointList from = Apply(truth.Inverse(), to);
  rp::AssessmentOptions options;
  options.FREThreshold = 1.0;
  options.FLE = 0.25;
  options.Target = Eigen::Vector3d(10, 20, 30);
  auto a = rp::AssessRegistration(from, to, options);
  EXPECT_TRUE(a.Accepted) << a.Reason;
  EXPECT_NE(a.Reason.find("within the threshold 1.000 mm"), std::string::npos) << a.Reason;
  EXPECT_TRUE(a.Warnings.empty());
  EXPECT_NEAR(a.PredictedTREAtTarget, rp::TREPredictor(to, 0.25).PredictRMS(*options.Target), 1e-12);
  EXPECT_NEAR(a.ExpectedFRE, 0.25 * std::sqrt(1 - 2.0 / 6), 1e-12);

  PointList moved = to;
  moved[2] += Eigen::Vector3d(0, 0, 8);
  a = rp::AssessRegistration(from, moved, options);
  EXPECT_FALSE(a.Accepted);
  EXPECT_NE(a.Reason.find("exceeds the threshold 1.000 mm"), std::string::npos) << a.Reason;
  ASSERT_FALSE(a.Warnings.empty());
  EXPECT_NE(a.Warnings[0].find("expected from FLE"), std::string::npos) << a.Warnings[0];
  ASSERT_EQ(a.Suspects.size(), 1u);
  EXPECT_EQ(a.Suspects[0].Index, 2);

  a = rp::AssessRegistration(PointList(from.begin(), from.begin() + 2), PointList(to.begin(), to.begin() + 2), options);
  EXPECT_FALSE(a.Accepted);
  EXPECT_NE(a.Reason.find("refused: fewer than 3"), std::string::npos) << a.Reason;
}

TEST(PairedPoint, MismatchedHandednessIsFlaggedByALargeFRE) {
  // The 'to' points in a left-handed frame (one axis flipped, e.g. an image whose L-R axis was
  // written reversed): no rotation maps them, the FRE is large, the registration is rejected.
  std::mt19937 rng(8);
  const PointList ras = RandomPoints(rng, 4, 60);
  const SimilarityTransform truth = RandomTransform(rng, false);
  const PointList tracker = Apply(truth.Inverse(), ras);
  PointList mirrored;
  for (const auto& p : ras) mirrored.emplace_back(-p.x(), p.y(), p.z());
  rp::AssessmentOptions options;
  options.FREThreshold = 2.0;
  options.FLE = 0.25;
  const auto a = rp::AssessRegistration(tracker, mirrored, options);
  EXPECT_FALSE(a.Accepted);
  EXPECT_GT(a.Solution.FRE, 10 * a.ExpectedFRE);
  EXPECT_FALSE(a.Warnings.empty());

  // Relabelling RAS as LPS negates two axes: that is a 180° rotation about S, not a change of
  // handedness, so a rigid registration absorbs it exactly (FRE cannot reveal it).
  PointList lps;
  for (const auto& p : ras) lps.emplace_back(-p.x(), -p.y(), p.z());
  const auto relabelled = rp::AssessRegistration(tracker, lps, options);
  EXPECT_TRUE(relabelled.Accepted);
  EXPECT_LT(relabelled.Solution.FRE, 1e-9);
}

TEST(PairedPoint, PredictedTREMapOnASurface) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(80);
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(12);
  sphere->Update();
  vtkPolyData* surface = sphere->GetOutput();
  const PointList f = {{30, 0, 0}, {-30, 5, 0}, {0, 30, 10}, {0, -30, -5}};
  const rp::TREPredictor predictor(f, 0.35);
  const double largest = rp::AddPredictedTREArray(surface, predictor);
  vtkDataArray* values = surface->GetPointData()->GetScalars();
  ASSERT_NE(values, nullptr);
  EXPECT_STREQ(values->GetName(), "PredictedTRE");
  ASSERT_EQ(values->GetNumberOfTuples(), surface->GetNumberOfPoints());
  double maxValue = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i) {
    double p[3];
    surface->GetPoint(i, p);
    EXPECT_NEAR(values->GetTuple1(i), predictor.PredictRMS(Eigen::Vector3d(p[0], p[1], p[2])), 1e-12);
    maxValue = std::max(maxValue, values->GetTuple1(i));
    EXPECT_GT(values->GetTuple1(i), predictor.PredictRMS(predictor.Centroid()));  // far from the centroid
  }
  EXPECT_DOUBLE_EQ(largest, maxValue);
}

TEST(SurfaceICP, TrimmedICPRecoversThePoseAndIgnoresOutliers) {
  // An ellipsoid (no rotational symmetry) and points digitized on it in tracker coordinates,
  // 10 % of them 10 mm off the surface; start 4° and 3 mm away from the truth.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1);
  sphere->SetThetaResolution(60);
  sphere->SetPhiResolution(40);
  vtkNew<vtkTransform> scale;
  scale->Scale(60, 40, 25);
  vtkNew<vtkTransformPolyDataFilter> ellipsoid;
  ellipsoid->SetInputConnection(sphere->GetOutputPort());
  ellipsoid->SetTransform(scale);
  ellipsoid->Update();
  vtkPolyData* surface = ellipsoid->GetOutput();

  std::mt19937 rng(9);
  const SimilarityTransform truth = RandomTransform(rng, false);  // tracker → RAS
  const SimilarityTransform inverse = truth.Inverse();
  PointList digitized;
  std::uniform_int_distribution<vtkIdType> pick(0, surface->GetNumberOfPoints() - 1);
  for (int i = 0; i < 200; ++i) {
    double p[3];
    surface->GetPoint(pick(rng), p);
    Eigen::Vector3d ras(p[0], p[1], p[2]);
    if (i % 10 == 0) ras *= 1 + 10 / ras.norm();  // 10 mm outward: off the surface
    digitized.push_back(inverse.Apply(ras));
  }
  SimilarityTransform start = truth;
  start.Rotation = Eigen::AngleAxisd(4 * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
                   truth.Rotation;
  start.Translation += Eigen::Vector3d(3, 0, 0);
  rp::SurfaceICPOptions options;
  options.InlierFraction = 0.85;
  const auto result = rp::RefineWithSurfaceICP(digitized, surface, start, options);
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_LT(result.Iterations, 30);  // point-to-plane: a few iterations, not hundreds
  EXPECT_LT(rp::RotationDifferenceDegrees(result.Transform.Rotation, truth.Rotation), 0.01);
  EXPECT_LT((result.Transform.Translation - truth.Translation).norm(), 0.05);
  EXPECT_LT(result.InlierRMS, 0.01);
  EXPECT_GT(result.AllRMS, 2.0);  // the outliers are still 10 mm away, reported separately
  EXPECT_EQ(result.Inliers, 170u);

  EXPECT_FALSE(rp::RefineWithSurfaceICP(PointList(2, Eigen::Vector3d::Zero()), surface, start).Ok);
  vtkNew<vtkPolyData> empty;
  EXPECT_FALSE(rp::RefineWithSurfaceICP(digitized, empty, start).Ok);
}

}  // namespace
