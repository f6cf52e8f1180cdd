// Rigid CT<->MR registration on the knee phantom, scored against the known CT-to-MR pose at
// the bone surfaces (analytic surface points).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <vtkTransform.h>

#include "rpKneePhantom.h"
#include "rpVolumeRegistration.h"

namespace {

const rp::KneePhantom& Phantom() {
  static rp::KneePhantom phantom;
  static bool made = false;
  if (!made) {
    rp::KneePhantomOptions options;
    options.GenerateLabels = false;
    std::string error;
    made = rp::GenerateKneePhantom(options, phantom, error);
    EXPECT_TRUE(made) << error;
  }
  return phantom;
}

std::vector<std::array<double, 3>> BoneSurface(const rp::KneeModel& model) {
  // Inside the small CT's field of view (|x|,|y| < 76 mm, |z| < 79 mm).
  const double bounds[6] = {-75, 75, -75, 75, -78, 78};
  std::vector<std::array<double, 3>> points;
  for (auto s : {rp::KneeStructure::Femur, rp::KneeStructure::Tibia, rp::KneeStructure::Patella,
                 rp::KneeStructure::Fibula}) {
    const auto p = model.SurfacePoints(s, 500, bounds);
    points.insert(points.end(), p.begin(), p.end());
  }
  return points;
}

// The defaults: 4 levels (8, 4, 2, 1), 10 % sampling, 32 bins.
rp::RigidRegistrationOptions FastOptions() { return rp::RigidRegistrationOptions(); }

}  // namespace

TEST(VolumeRegistration, RecoversThePhantomPoseFromTheScannerStart) {
  const rp::KneePhantom& phantom = Phantom();
  const auto surface = BoneSurface(*phantom.Model);
  ASSERT_GT(surface.size(), 1500u);
  vtkNew<vtkMatrix4x4> identity;
  const double startError = rp::TransformRMSDifference(identity, phantom.CTToMR, surface);
  EXPECT_GT(startError, 15.0);  // the MR really is in another pose
  rp::RigidRegistrationResult result;
  std::string error;
  double lastFraction = 0.0;
  ASSERT_TRUE(rp::RegisterVolumesRigid(phantom.CT, phantom.MR, FastOptions(), result, error,
                                       [&](double f, const std::string&) { lastFraction = f; }))
      << error;
  const double rms = rp::TransformRMSDifference(result.FixedToMoving, phantom.CTToMR, surface);
  std::printf("[registration] start %.2f mm -> %.3f mm RMS at the bone surface, %u iterations, %.2f s, %s\n",
              startError, rms, result.Iterations, result.Seconds, result.StopReason.c_str());
  EXPECT_TRUE(result.Converged) << result.StopReason;
  EXPECT_LT(rms, 1.0);
  EXPECT_DOUBLE_EQ(lastFraction, 1.0);
  // MovingToFixed is the inverse (the transform node's "to parent" MRToCT).
  vtkNew<vtkMatrix4x4> product;
  vtkMatrix4x4::Multiply4x4(result.MovingToFixed, result.FixedToMoving, product);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(product->GetElement(r, c), r == c ? 1.0 : 0.0, 1e-9);
}

TEST(VolumeRegistration, ConvergesFrom20DegreesAnd30mmOff) {
  const rp::KneePhantom& phantom = Phantom();
  const auto surface = BoneSurface(*phantom.Model);
  // Start = truth composed with a 20 degree rotation about an oblique axis through the knee
  // centre and a 30 mm shift.
  vtkNew<vtkTransform> start;
  start->PostMultiply();
  start->RotateWXYZ(20.0, 1.0, 1.0, 0.5);
  start->Translate(30.0 * 0.6, 0.0, 30.0 * 0.8);
  start->Concatenate(phantom.CTToMR);
  rp::RigidRegistrationOptions options = FastOptions();
  options.InitialFixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();
  options.InitialFixedToMoving->DeepCopy(start->GetMatrix());
  const double startError = rp::TransformRMSDifference(options.InitialFixedToMoving, phantom.CTToMR, surface);
  EXPECT_GT(startError, 30.0);
  rp::RigidRegistrationResult result;
  std::string error;
  ASSERT_TRUE(rp::RegisterVolumesRigid(phantom.CT, phantom.MR, options, result, error)) << error;
  const double rms = rp::TransformRMSDifference(result.FixedToMoving, phantom.CTToMR, surface);
  std::printf("[registration] 20deg/30mm start %.2f mm -> %.3f mm RMS, %u iterations, %.2f s\n", startError, rms,
              result.Iterations, result.Seconds);
  EXPECT_TRUE(result.Converged) << result.StopReason;
  EXPECT_LT(rms, 1.0);
}

TEST(VolumeRegistration, NonConvergenceAndCancelAreReported) {
  const rp::KneePhantom& phantom = Phantom();
  rp::RigidRegistrationOptions options = FastOptions();
  options.ShrinkFactors = {4};
  options.SmoothingSigmasMM = {2.0};
  options.MaxIterationsPerLevel = 3;
  rp::RigidRegistrationResult result;
  std::string error;
  ASSERT_TRUE(rp::RegisterVolumesRigid(phantom.CT, phantom.MR, options, result, error)) << error;
  EXPECT_FALSE(result.Converged);
  EXPECT_NE(result.StopReason.find("aximum number of iterations"), std::string::npos) << result.StopReason;

  std::atomic<bool> cancel{false};
  int calls = 0;
  EXPECT_FALSE(rp::RegisterVolumesRigid(
      phantom.CT, phantom.MR, FastOptions(), result, error,
      [&](double, const std::string&) {
        if (++calls == 5) cancel = true;
      },
      &cancel));
  EXPECT_NE(error.find("cancelled"), std::string::npos) << error;
  EXPECT_LT(calls, 20);

  rp::ImageVolume empty;
  EXPECT_FALSE(rp::RegisterVolumesRigid(empty, phantom.MR, options, result, error));
  EXPECT_NE(error.find("empty"), std::string::npos);
  // Volumes that do not overlap at all: a clear failure, not a crash.
  rp::RigidRegistrationOptions far = FastOptions();
  far.InitialFixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();
  far.InitialFixedToMoving->SetElement(0, 3, 5000.0);
  EXPECT_FALSE(rp::RegisterVolumesRigid(phantom.CT, phantom.MR, far, result, error));
  EXPECT_NE(error.find("registration failed"), std::string::npos) << error;
}
