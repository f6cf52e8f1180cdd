// The score of an execution against analytic executions (issue 38, "Proven"): a path offset by a
// known distance and tilted by a known angle gives those numbers (1e-6 mm, 1e-6°); the volume an
// offset drilled tunnel leaves outside the plan's cylinder is the lens's closed form within the
// voxel error; breach grades and clearances of known geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "rpExecutionScore.h"
#include "rpTestAxis.h"

namespace {

using rp::Vec3;

using rptest::Axis;

// A straight path from `start` along `direction` for `length` mm, one point every `step` mm.
std::vector<Vec3> Line(const Vec3& start, const Vec3& direction, double length, double step = 0.05) {
  std::vector<Vec3> path;
  const int n = static_cast<int>(std::round(length / step));
  for (int i = 0; i <= n; ++i) path.push_back(start + rp::Normalized(direction) * (length * i / n));
  return path;
}

TEST(ExecutionScore, AnOffsetAndTiltedPathGivesItsOffsetsAngleAndDepthError) {
  const Vec3 entry{12, -30, 55};
  const Vec3 u = rp::Normalized(Vec3{0.3, 0.2, -1});
  const double length = 42;
  const rp::TrajectoryAxis plan = Axis(entry, entry + u * length);
  const Vec3 w = rp::Normalized(rp::Cross(u, {1, 0, 0}));  // across the axis
  const Vec3 v = rp::Cross(u, w);                          // across it too
  for (double offset : {0.0, 0.37, 1.5}) {
    for (double degrees : {0.0, 0.8, 3.0, 10.0}) {
      const double theta = degrees * M_PI / 180;
      const Vec3 tilted = u * std::cos(theta) + w * std::sin(theta);
      const Vec3 start = entry + v * offset;  // crosses the entry plane `offset` mm off the entry
      const double overshoot = 1.25;          // drilled 1.25 mm deeper than the target
      rp::ExecutionInput input;
      input.Plan = plan;
      input.PlanDiameterMm = 4;
      input.Path = Line(start, tilted, (length + overshoot) / std::cos(theta));
      rp::ExecutionScore score;
      std::string error;
      ASSERT_TRUE(rp::ScoreExecution(input, score, error)) << error;
      const double lateral = length * std::tan(theta);
      EXPECT_NEAR(score.EntryOffsetMm, offset, 1e-6);
      EXPECT_NEAR(score.TipOffsetMm, std::hypot(offset, lateral), 1e-6);
      EXPECT_NEAR(score.AngleDeg, degrees, 1e-6);
      EXPECT_NEAR(score.DepthErrorMm, overshoot, 1e-6);
      EXPECT_NEAR(score.MaxDeviationMm, std::hypot(offset, (length + overshoot) * std::tan(theta)), 1e-6);
    }
  }
}

TEST(ExecutionScore, WhereTheToolDweltDoesNotTiltTheExecutedAxis) {
  const rp::TrajectoryAxis plan = Axis({0, 0, 0}, {0, 0, -30});
  rp::ExecutionInput input;
  input.Plan = plan;
  input.Path = Line({0.5, 0, 0}, {0.05, 0, -1}, 30);
  const Vec3 last = input.Path.back();
  rp::ExecutionScore straight, dwelt;
  std::string error;
  ASSERT_TRUE(rp::ScoreExecution(input, straight, error));
  for (int i = 0; i < 5000; ++i) input.Path.push_back(last + Vec3{1e-3 * std::sin(i), 0, 0});  // 5 s at the bottom
  ASSERT_TRUE(rp::ScoreExecution(input, dwelt, error));
  EXPECT_NEAR(dwelt.AngleDeg, straight.AngleDeg, 0.01);
  EXPECT_NEAR(dwelt.EntryOffsetMm, straight.EntryOffsetMm, 0.01);
}

// Lens area of two circles of radius r whose centres are d apart.
double Lens(double r, double d) { return 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d); }

TEST(ExecutionScore, TheVolumeOutsideThePlanOfAnOffsetTunnelIsTheLensClosedForm) {
  const double r = 2, length = 20;
  const rp::TrajectoryAxis plan = Axis({0, 0, 0}, {0, 0, -length});
  for (double d : {0.0, 0.5, 1.0, 2.5}) {
    rp::ExecutionInput input;
    input.Plan = plan;
    input.PlanDiameterMm = 2 * r;
    input.ToolRadiusMm = r;  // a burr swept from the entry plane to the target plane, d mm off
    input.SweepVoxelMm = 0.1;
    input.Path = Line({d, 0, 0}, {0, 0, -1}, length);
    rp::ExecutionScore score;
    std::string error;
    ASSERT_TRUE(rp::ScoreExecution(input, score, error)) << error;
    ASSERT_TRUE(score.HasVolume);
    // The tunnel's cylinder outside the planned one, and the burr's two half-balls beyond the planes.
    const double overlap = d < 2 * r ? Lens(r, d) : 0;
    const double expected = length * (M_PI * r * r - overlap) + 4.0 / 3.0 * M_PI * r * r * r;
    const double drilled = length * M_PI * r * r + 4.0 / 3.0 * M_PI * r * r * r;
    EXPECT_NEAR(score.OutsideVolumeMm3, expected, 0.01 * drilled) << d;
    EXPECT_NEAR(score.DrilledVolumeMm3, drilled, 0.01 * drilled) << d;
  }
}

TEST(ExecutionScore, RemovedVoxelsAreCountedInsideAndOutsideThePlan) {
  rp::ExecutionInput input;
  input.Plan = Axis({0, 0, 0}, {0, 0, -10});
  input.PlanDiameterMm = 2;
  input.Path = Line({0, 0, 0}, {0, 0, -1}, 10);
  input.Removed = {{{0, 0, -5}, 0.008}, {{0.9, 0, -5}, 0.008}, {{1.1, 0, -5}, 0.004}, {{0, 0, -10.5}, 0.008}, {{0, 0, 0.2}, 0.002}};
  rp::ExecutionScore score;
  std::string error;
  ASSERT_TRUE(rp::ScoreExecution(input, score, error));
  EXPECT_NEAR(score.DrilledVolumeMm3, 0.030, 1e-15);
  EXPECT_NEAR(score.OutsideVolumeMm3, 0.014, 1e-15);
}

TEST(ExecutionScore, BreachGradeOfAToolComingOutOfTheBone) {
  // A bone slab x ∈ [−5, 5] (a closed box); the plan runs down its middle from outside.
  rp::MeshSignedDistance bone;
  std::string error;
  ASSERT_TRUE(bone.Build(rp::shapes::Box({-5, -20, -60}, {5, 20, 0}), error)) << error;
  const rp::TrajectoryAxis plan = Axis({0, 0, 10}, {0, 0, -40});
  for (const auto& [x, breach, grade] : {std::tuple{2.0, 0.0, 0}, std::tuple{4.0, 1.0, 1}, std::tuple{6.5, 3.5, 2},
                                          std::tuple{8.0, 5.0, 3}, std::tuple{10.0, 7.0, 4}}) {
    rp::ExecutionInput input;
    input.Plan = plan;
    input.PlanDiameterMm = 4;
    input.ToolRadiusMm = 2;
    input.Bone = &bone;
    input.Path = Line({x, 0, 10}, {0, 0, -1}, 50);
    rp::ExecutionScore score;
    ASSERT_TRUE(rp::ScoreExecution(input, score, error)) << error;
    EXPECT_TRUE(score.HasBreach);
    EXPECT_NEAR(score.BreachMm, breach, 1e-9) << x;
    EXPECT_EQ(score.BreachGrade, grade) << x;
  }
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(0), 0);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(1.99), 1);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(2.0), 2);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(3.99), 2);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(4.0), 3);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(6.0), 3);
  EXPECT_EQ(rp::GertzbeinRobbinsGrade(6.01), 4);
}

TEST(ExecutionScore, ClearanceToAStructureIsTheToolSurfacesClosestApproach) {
  rp::MeshSignedDistance vessel;
  std::string error;
  ASSERT_TRUE(vessel.Build(rp::shapes::Box({6, -3, -25}, {12, 3, -15}), error)) << error;  // a box: exact distances
  rp::ExecutionInput input;
  input.Plan = Axis({0, 0, 0}, {0, 0, -40});
  input.ToolRadiusMm = 1.5;
  input.Structures.push_back({"vessel", &vessel, 3.0});
  input.Path = Line({1, 0, 0}, {0, 0, -1}, 40);
  rp::ExecutionScore score;
  ASSERT_TRUE(rp::ScoreExecution(input, score, error)) << error;
  ASSERT_EQ(score.Clearance.size(), 1u);
  EXPECT_NEAR(score.Clearance[0].ClosestMm, 6 - 1 - 1.5, 1e-9);
  EXPECT_GE(score.Clearance[0].DepthMm, 15 - 1e-9);
  EXPECT_LE(score.Clearance[0].DepthMm, 25 + 1e-9);
  EXPECT_FALSE(score.Clearance[0].WithinMargin);
  input.Structures[0].MarginMm = 4;
  ASSERT_TRUE(rp::ScoreExecution(input, score, error));
  EXPECT_TRUE(score.Clearance[0].WithinMargin);
}

TEST(ExecutionScore, APathThatDoesNotMoveIsAClearError) {
  rp::ExecutionInput input;
  input.Plan = Axis({0, 0, 0}, {0, 0, -40});
  input.Path = {{1, 2, 3}, {1, 2, 3}};
  rp::ExecutionScore score;
  std::string error;
  EXPECT_FALSE(rp::ScoreExecution(input, score, error));
  EXPECT_NE(error.find("fewer than two distinct points"), std::string::npos) << error;
  input.Path = Line({0, 0, -5}, {1, 0, 0}, 10);  // across the plan: never reaches the entry plane
  EXPECT_FALSE(rp::ScoreExecution(input, score, error));
  EXPECT_NE(error.find("parallel"), std::string::npos) << error;
}

}  // namespace
