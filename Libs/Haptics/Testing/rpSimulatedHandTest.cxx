// The hand to test guidance with: tremor in 8–12 Hz at the RMS asked for, drift at the speed asked
// for, both reproducible from the seed; the stylus pushed off the hand's path by F/K (the hand's
// stiffness, stiffer along the shaft than across it).
#include <gtest/gtest.h>

#include <cmath>

#include "rpSimulatedDevice.h"

namespace {

using rp::Vec3;

rp::HandNoise Noise(double tremor, double drift, uint64_t seed) {
  rp::HandNoise n;
  n.TremorMm = tremor;
  n.DriftMmPerS = drift;
  n.Seed = seed;
  return n;
}

TEST(SimulatedHand, TremorHasTheAmplitudeAndBandAskedFor) {
  const rp::HandNoiseField field(Noise(0.2, 0, 42));
  // RMS over 30 s at 5 kHz; the frequency from the zero crossings of each axis.
  double sum2 = 0;
  int crossings[3] = {0, 0, 0};
  Vec3 last = field.Tremor(0);
  const int n = 150000;
  for (int i = 1; i <= n; ++i) {
    const Vec3 v = field.Tremor(i / 5000.0);
    sum2 += rp::Norm2(v);
    for (int a = 0; a < 3; ++a) crossings[a] += (v[a] > 0) != (last[a] > 0);
    last = v;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.2, 0.2 * 0.05);
  for (int a = 0; a < 3; ++a) {
    const double hz = crossings[a] / 2.0 / 30.0;
    EXPECT_GT(hz, 8.0) << a;
    EXPECT_LT(hz, 12.0) << a;
  }
}

TEST(SimulatedHand, DriftMovesAtTheSpeedAskedForAndStaysBounded) {
  const rp::HandNoise noise = Noise(0, 1.0, 7);
  const rp::HandNoiseField field(noise);
  EXPECT_NEAR(rp::Norm(field.Drift(0)), 0, 1e-15);
  double farthest = 0;
  for (int i = 0; i < 4000; ++i) {
    const double t = 0.01 * i, h = 1e-6;
    EXPECT_NEAR(rp::Norm(field.Drift(t + h) - field.Drift(t - h)) / (2 * h), 1.0, 1e-6);
    farthest = std::max(farthest, rp::Norm(field.Drift(t)));
  }
  EXPECT_LE(farthest, 1.0 * noise.DriftPeriodS / M_PI + 1e-9);
  EXPECT_GT(farthest, 0.99 * noise.DriftPeriodS / M_PI);
  EXPECT_NEAR(rp::Norm(field.Drift(1.0)), 1.0, 0.05);  // about D·t in the first second
}

TEST(SimulatedHand, TheSameSeedGivesTheSameHandAndAnotherSeedAnother) {
  const rp::HandNoiseField a(Noise(0.2, 1, 3)), b(Noise(0.2, 1, 3)), c(Noise(0.2, 1, 4));
  for (double t : {0.0, 0.37, 1.5, 9.0}) {
    EXPECT_EQ(rp::Norm(a.Offset(t) - b.Offset(t)), 0.0);
    if (t > 0) {
      EXPECT_GT(rp::Norm(a.Offset(t) - c.Offset(t)), 1e-3);
    }
  }
}

// A constant force pushes the stylus off where the hand means it to be by F/K: K along the shaft
// (the stylus's +z) and across it differ.
TEST(SimulatedHand, AConstantForcePushesTheStylusByItOverTheHandsStiffness) {
  rp::HandImpedance mechanics;
  auto device = std::make_unique<rp::SimulatedDevice>();
  device->SetTrajectory(rp::WaypointTrajectory::Line({1, 2, 3}, {1, 2, 3}, 1));
  device->SetHand(std::make_unique<rp::SimulatedHand>(rp::HandNoise{}, mechanics, device->Info().PhysicalDamping));
  std::string error;
  ASSERT_TRUE(device->Open(error));
  rp::DeviceState state;
  device->WriteForce({0.3, 0, 0});  // across the shaft
  for (int i = 0; i <= 3000; ++i) ASSERT_TRUE(device->Read(i * 0.001, state));
  EXPECT_NEAR(state.StylusToDevice.T.x - 1, 0.3 / mechanics.LateralStiffness, 1e-6);
  device->WriteForce({0, 0, -0.5});  // along it
  for (int i = 3001; i <= 6000; ++i) ASSERT_TRUE(device->Read(i * 0.001, state));
  EXPECT_NEAR(state.StylusToDevice.T.z - 3, -0.5 / mechanics.AxialStiffness, 1e-6);
  EXPECT_NEAR(state.StylusToDevice.T.x - 1, 0, 1e-6);
}

}  // namespace
