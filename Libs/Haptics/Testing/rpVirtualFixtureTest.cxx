// The virtual fixtures against closed forms (issue 38, "Proven"): the pull onto a straight axis is
// the spring's on the perpendicular distance; the proxy held on a sphere stays at its radius while
// the device circles inside the threshold; the depth stop is never crossed at 0.5 m/s (nor in one
// tick at any speed); the forbidden region is never entered; events (switching, capture, release,
// a new snapshot) change the force by at most the device's MaxForceRate per tick; the tick does
// not allocate.
#include <gtest/gtest.h>

#include <cmath>

#include "rpAllocationCounter.h"
#include "rpAxisGuidance.h"
#include "rpDepthStop.h"
#include "rpDeviceProfiles.h"
#include "rpFixtureConstraint.h"
#include "rpFixtureRenderer.h"
#include "rpForbiddenRegion.h"
#include "rpHapticRenderer.h"
#include "rpHapticsTestScenes.h"
#include "rpPlanFixtures.h"
#include "rpSurfaceConstraint.h"

namespace {

using rp::Vec3;
constexpr double Period = 0.001;

rp::DeviceInfo Omni() {
  rp::DeviceProfile profile;
  std::string error;
  EXPECT_TRUE(rp::FindDeviceProfile("omni", profile, error));
  return profile.Info;
}

rp::TrajectoryAxis Axis(const Vec3& entry, const Vec3& target) {
  rp::TrajectoryAxis axis;
  std::string error;
  EXPECT_TRUE(rp::TrajectoryAxis::Make(entry, target, axis, error)) << error;
  return axis;
}

rp::FixtureTuning Tuning(double k, double b, double capture, double release) {
  rp::FixtureTuning t;
  t.Stiffness = k;
  t.Damping = b;
  t.Capture = capture;
  t.Release = release;
  return t;
}

std::unique_ptr<rp::FixtureSet> One(std::shared_ptr<const rp::VirtualFixture> f, const rp::FixtureTuning& t,
                                    bool enabled = true) {
  auto set = std::make_unique<rp::FixtureSet>();
  std::string error;
  EXPECT_TRUE(set->Add(std::move(f), t, enabled, error)) << error;
  return set;
}

// Ticks the renderer with the tool at `tip` until the fades settled; returns the output.
const rp::FixtureOutput& Settle(rp::FixtureRenderer& r, const rp::FixtureSet* set, const Vec3& tip, int ticks = 50) {
  for (int i = 0; i + 1 < ticks; ++i) r.Update(set, rp::FixtureTool{tip, {}, 0}, Period, Period);
  return r.Update(set, rp::FixtureTool{tip, {}, 0}, Period, Period);
}

TEST(TrajectoryAxis, DepthOffsetAngleAndLineFit) {
  const rp::TrajectoryAxis axis = Axis({1, 2, 3}, {1, 2, 43});
  EXPECT_DOUBLE_EQ(axis.Length(), 40);
  EXPECT_DOUBLE_EQ(axis.Depth({5, -1, 13}), 10);
  EXPECT_DOUBLE_EQ(axis.Distance({4, 6, 13}), 5);
  EXPECT_NEAR(rp::AngleBetweenDegrees({0, 0, 1}, {0, std::sin(1e-4), std::cos(1e-4)}), 1e-4 * 180 / M_PI, 1e-15);
  rp::TrajectoryAxis bad;
  std::string error;
  EXPECT_FALSE(rp::TrajectoryAxis::Make({1, 1, 1}, {1, 1, 1}, bad, error));
  EXPECT_NE(error.find("zero length"), std::string::npos);
  // Points on a known line (with alternating offsets across it that cancel): its direction exactly.
  std::vector<Vec3> points;
  const Vec3 d = rp::Normalized(Vec3{1, 2, -2});
  for (int i = 0; i < 101; ++i) points.push_back(Vec3{10, 20, 30} + d * (0.5 * i) + Vec3{2, -1, 0} * (i % 2 ? 0.1 : -0.1));
  Vec3 c, u;
  ASSERT_TRUE(rp::FitLine(points.data(), points.size(), c, u));
  EXPECT_GT(rp::Dot(u, d), 0);
}

TEST(AxisGuidance, PullsWithTheSpringOnThePerpendicularDistanceAndIsFreeAlongTheAxis) {
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, rp::Normalized(Vec3{1, 1, 1}) * 50);
  const auto set = One(std::make_shared<rp::AxisGuidance>(1, "tunnel", axis), Tuning(0.5, 0.001, 3, 4));
  rp::FixtureRenderer r;
  r.SetDevice(Omni());
  const Vec3 across = rp::Normalized(rp::Cross(axis.Direction(), {0, 0, 1}));
  const Vec3 tip = axis.PointAt(20) + across * 1.7;
  const rp::FixtureOutput& held = Settle(r, set.get(), tip);
  ASSERT_EQ(held.Fixtures[0].Weight, 1.0);
  const Vec3 expected = across * (-0.5 * 1.7);
  EXPECT_NEAR(rp::Norm(held.Force - expected), 0, 1e-12);
  // Moving along the axis at 50 mm/s: the same force, nothing along the axis (free along it).
  for (int i = 1; i <= 200; ++i) {
    const rp::FixtureOutput& o = r.Update(set.get(), {tip + axis.Direction() * (0.05 * i), {}, 0}, Period, Period);
    EXPECT_NEAR(rp::Dot(o.Force, axis.Direction()), 0, 1e-12);
    EXPECT_NEAR(rp::Norm(o.Force - expected), 0, 1e-12);
  }
  // Off the axis by other distances: F = k·d exactly, towards the axis.
  for (double d : {0.0, 0.3, 1.0, 2.5}) {
    const rp::FixtureOutput& o = Settle(r, set.get(), axis.PointAt(30) + across * d);
    EXPECT_NEAR(rp::Norm(o.Force), 0.5 * d, 1e-12) << d;
  }
}

TEST(AxisGuidance, PullsTheToolsDirectionOnADeviceWithTorque) {
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, {0, 0, -40});
  rp::FixtureTuning t = Tuning(0.5, 0, 3, 4);
  t.AngularStiffness = 200;  // N·mm/rad
  const auto set = One(std::make_shared<rp::AxisGuidance>(1, "tunnel", axis), t);
  rp::FixtureRenderer r;
  const double tilt = 0.1;  // rad
  const rp::FixtureTool tool{{0, 0, -10}, {std::sin(tilt), 0, -std::cos(tilt)}, 0};
  for (int i = 0; i < 20; ++i) r.Update(set.get(), tool, Period, Period);
  const Vec3 torque = r.Output().Torque;
  EXPECT_NEAR(rp::Norm(torque), 200 * tilt, 1e-9);
  // It turns the tool towards the axis: about +y takes (sin, 0, −cos) towards (0, 0, −1).
  EXPECT_GT(rp::Dot(rp::Cross(torque, tool.Direction), axis.Direction() - tool.Direction), 0);
}

TEST(SurfaceConstraint, HoldsTheProxyOnASphereAtItsRadiusWhileTheDeviceCirclesInside) {
  const Vec3 center{3, -2, 7};
  const double radius = 20;
  const auto set = One(std::shared_ptr<rp::VirtualFixture>(rp::SurfaceConstraint::Sphere(1, "shell", center, radius)),
                       Tuning(0.4, 0.0005, 2, 3));
  rp::FixtureRenderer r;
  r.SetDevice(Omni());
  // Start on the circle 1 mm inside the sphere, then go round it at 100 mm/s for two turns.
  const double inside = radius - 1;
  double worst = 0;
  int engaged = 0;
  for (int i = 0; i < 2500; ++i) {
    const double a = 100.0 * i * Period / inside;
    const Vec3 tip = center + Vec3{inside * std::cos(a), inside * std::sin(a), 0.3 * std::sin(3 * a)};
    r.Update(set.get(), {tip, {}, 0}, Period, Period);
    const rp::FixtureReport& f = r.Output().Fixtures[0];
    engaged += f.Engaged;
    // The proxy is where the spring pulls: on the sphere, at the point closest to the tool.
  }
  EXPECT_EQ(engaged, 2500);
  // Read the proxy through the force: tip + F/k (fully faded in, no damping across a circle's normal).
  for (int i = 0; i < 100; ++i) {
    const double a = 0.05 * i;
    const Vec3 tip = center + Vec3{inside * std::cos(a), inside * std::sin(a), 0.0};
    const rp::FixtureOutput& o = Settle(r, set.get(), tip, 3);
    const Vec3 proxy = tip + o.Force / 0.4;
    worst = std::max(worst, std::fabs(rp::Norm(proxy - center) - radius));
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(SurfaceConstraint, CapturesWithinTheThresholdAndReleasesBeyondTheLargerDistance) {
  const auto set = One(std::shared_ptr<rp::VirtualFixture>(rp::SurfaceConstraint::Plane(1, "cut", {0, 0, 0}, {0, 0, 1})),
                       Tuning(0.4, 0, 2, 3));
  rp::FixtureRenderer r;
  auto engagedAt = [&](double z) { return Settle(r, set.get(), {1, 2, z}, 3).Fixtures[0].Engaged; };
  EXPECT_FALSE(engagedAt(2.5));  // approaching: not yet
  EXPECT_TRUE(engagedAt(1.9));   // within the threshold: captured
  EXPECT_TRUE(engagedAt(2.9));   // hysteresis: held until beyond the release distance
  EXPECT_FALSE(engagedAt(3.1));  // released
  EXPECT_FALSE(engagedAt(2.5));  // and not captured again before the threshold
  EXPECT_TRUE(engagedAt(-1.5));  // from below too
}

TEST(SurfaceConstraint, OnAMeshTheProxyIsOnTheMesh) {
  const rp::TriangleMesh sphere = rp::shapes::Sphere({0, 0, 0}, 15, 4);
  std::string error;
  auto fixture = rp::SurfaceConstraint::Mesh(1, "bone", sphere, error);
  ASSERT_TRUE(fixture) << error;
  rp::BVH tree;
  tree.Build(sphere);
  const auto set = One(std::shared_ptr<rp::VirtualFixture>(std::move(fixture)), Tuning(0.4, 0, 2, 3));
  rp::FixtureRenderer r;
  for (int i = 0; i < 300; ++i) {
    const double a = 0.01 * i;
    const Vec3 tip{14 * std::cos(a), 14 * std::sin(a), 1};
    const rp::FixtureOutput& o = Settle(r, set.get(), tip, 2);
    const Vec3 proxy = tip + o.Force / 0.4;
    rp::ClosestPointHit hit;
    ASSERT_TRUE(tree.ClosestPoint(proxy, 1, hit));
    EXPECT_LT(std::sqrt(hit.Distance2), 1e-9);
  }
}

TEST(DepthStop, IsNeverCrossedAtHalfAMetrePerSecondNorInOneTickAtAnySpeed) {
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, rp::Normalized(Vec3{0.2, -0.3, -1}) * 35);
  const auto set = One(std::make_shared<rp::DepthStop>(1, "stop", axis), Tuning(0.6, 0.001, 4, 4));
  rp::FixtureRenderer r;
  r.SetDevice(Omni());
  const Vec3 across = rp::Normalized(rp::Cross(axis.Direction(), {1, 0, 0}));
  double deepest = -HUGE_VAL;
  // 0.5 m/s along the axis from 10 mm before the entry to 60 mm deep, wobbling 1 mm across it.
  r.Reset(axis.PointAt(-10));
  for (int i = 0; i <= 140; ++i) {
    const double depth = -10 + 0.5 * i;
    const Vec3 tip = axis.PointAt(depth) + across * std::sin(0.7 * i);
    const rp::FixtureOutput& o = r.Update(set.get(), {tip, {}, 0}, Period, Period);
    deepest = std::max(deepest, axis.Depth(o.Goal));
    if (depth > 36) {
      EXPECT_TRUE(o.Blocked);
      EXPECT_LT(rp::Dot(o.Force, axis.Direction()), 0);  // pushes back towards the entry
    }
  }
  EXPECT_LE(deepest, 35 + 1e-12);
  EXPECT_GE(deepest, 35 - 1e-12);
  // One tick from before the entry to 100 mm beyond the target (100 m/s): still held.
  rp::FixtureRenderer fast;
  fast.Reset(axis.PointAt(-5));
  const rp::FixtureOutput& o = fast.Update(set.get(), {axis.PointAt(135) + across, {}, 0}, Period, Period);
  EXPECT_LE(axis.Depth(o.Goal), 35 + 1e-12);
  // Beside the stop (beyond its capture radius) the tool passes; and a tool already beyond the
  // stop is not pushed back (one-sided).
  rp::FixtureRenderer beside;
  beside.Reset(axis.PointAt(30) + across * 5);
  EXPECT_NEAR(axis.Depth(beside.Update(set.get(), {axis.PointAt(40) + across * 5, {}, 0}, Period, Period).Goal), 40, 1e-9);
  rp::FixtureRenderer behind;
  behind.Reset(axis.PointAt(45));
  EXPECT_NEAR(axis.Depth(behind.Update(set.get(), {axis.PointAt(46), {}, 0}, Period, Period).Goal), 46, 1e-9);
  EXPECT_NEAR(rp::Norm(behind.Output().Force), 0, 1e-12);
}

TEST(ForbiddenRegion, IsNeverEnteredAtAnySpeedAndSlidesAlongTheWall) {
  const rp::TriangleMesh vessel = rp::shapes::Sphere({0, 0, 0}, 5, 3);
  std::string error;
  auto fixture = rp::ForbiddenRegion::Make(1, "popliteal", vessel, 2.0, error);
  ASSERT_TRUE(fixture) << error;
  const rp::MeshSignedDistance& field = fixture->Field();
  const auto set = One(std::shared_ptr<rp::VirtualFixture>(std::move(fixture)), Tuning(0.6, 0.001, 1, 1));
  const double radius = 1.0, clearance = 3.0;  // burr radius + margin
  // Straight through at 0.5 m/s, off-centre by several amounts; and in one tick through it all.
  for (double offset : {0.0, 2.0, 4.0, 6.0, 7.5}) {
    rp::FixtureRenderer r;
    r.SetDevice(Omni());
    r.Reset({-20, offset, 0});
    double nearest = HUGE_VAL;
    for (int i = 0; i <= 80; ++i) {
      const rp::FixtureOutput& o = r.Update(set.get(), {{-20 + 0.5 * i, offset, 0.3}, {}, radius}, Period, Period);
      nearest = std::min(nearest, field.SignedDistance(o.Goal));
    }
    EXPECT_GE(nearest, clearance - 1e-9) << offset;
  }
  rp::FixtureRenderer jump;
  jump.Reset({-20, 0.5, 0});
  EXPECT_GE(field.SignedDistance(jump.Update(set.get(), {{20, 0.5, 0}, {}, radius}, Period, Period).Goal), clearance - 1e-9);
  // Pressed in and moved round: the proxy slides on the wall (at the clearance, within the mesh's
  // distance field) and the spring pushes out.
  rp::FixtureRenderer slide;
  slide.Reset({-12, 0, 0});
  for (int i = 0; i < 400; ++i) {
    const double a = 0.01 * i;
    const Vec3 tip{-6.5 * std::cos(a), 6.5 * std::sin(a), 0.2};  // 1.5 mm inside the wall
    const rp::FixtureOutput& o = slide.Update(set.get(), {tip, {}, radius}, Period, Period);
    if (i < 10) continue;
    const double d = field.SignedDistance(o.Goal);
    EXPECT_GE(d, clearance - 1e-9);
    EXPECT_LT(d, clearance + 0.05);
    EXPECT_GT(rp::Dot(o.Force, tip), 0);
  }
}

TEST(ForbiddenRegion, DampsTheApproachWithinItsCaptureBandAndPushesNothingAtRest) {
  const rp::TriangleMesh vessel = rp::shapes::Sphere({0, 0, 0}, 5, 3);
  std::string error;
  auto fixture = rp::ForbiddenRegion::Make(1, "vessel", vessel, 1.0, error);
  ASSERT_TRUE(fixture) << error;
  const auto set = One(std::shared_ptr<rp::VirtualFixture>(std::move(fixture)), Tuning(0.6, 0.002, 3, 3));
  rp::FixtureRenderer r;
  r.Reset({-12, 0, 0});
  // At rest 1.5 mm before the wall (inside the 3 mm band): no force.
  EXPECT_NEAR(rp::Norm(Settle(r, set.get(), {-7.5, 0, 0}).Force), 0, 1e-12);
  // Approaching at 20 mm/s: a force against the approach.
  r.Update(set.get(), {{-7.48, 0, 0}, {}, 0}, Period, Period);
  EXPECT_LT(r.Output().Force.x, 0);
}

// Events change the force by at most MaxForceRate × period per tick.
TEST(FixtureEvents, SwitchingCaptureReleaseAndNewSnapshotsStepTheForceNoMoreThanTheDeviceAllows) {
  const rp::DeviceInfo omni = Omni();
  const double step = omni.MaxForceRate * Period;  // 0.35 N
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, {0, 0, -50});
  auto guide = std::make_shared<rp::AxisGuidance>(7, "tunnel", axis);
  const rp::FixtureTuning t = Tuning(0.6, 0.0, 3, 4);
  const auto on = One(guide, t, true);
  const auto off = on->WithKindEnabled(rp::FixtureKind::AxisGuidance, false);
  rp::FixtureRenderer r;
  r.SetDevice(omni);
  Vec3 last{};
  double largest = 0;
  auto tick = [&](const rp::FixtureSet* set, const Vec3& tip) {
    const Vec3 f = r.Update(set, {tip, {}, 0}, Period, Period).Force;
    largest = std::max(largest, rp::Norm(f - last));
    last = f;
    return f;
  };
  const Vec3 held{2.8, 0, -20};  // 2.8 mm off the axis: 1.68 N when fully on
  for (int i = 0; i < 5; ++i) tick(off.get(), held);
  for (int i = 0; i < 20; ++i) tick(on.get(), held);  // switched on
  EXPECT_NEAR(rp::Norm(last), 0.6 * 2.8, 1e-12);
  for (int i = 0; i < 20; ++i) tick(off.get(), held);  // switched off
  EXPECT_NEAR(rp::Norm(last), 0, 1e-12);
  EXPECT_LE(largest, step + 1e-12);
  // Capture: the tool jumps from outside the capture radius to just inside it.
  largest = 0;
  for (int i = 0; i < 5; ++i) tick(on.get(), {3.5, 0, -20});
  EXPECT_NEAR(rp::Norm(last), 0, 1e-12);
  for (int i = 0; i < 20; ++i) tick(on.get(), {2.95, 0, -20});
  EXPECT_NEAR(rp::Norm(last), 0.6 * 2.95, 1e-12);
  // Release beyond 4 mm (hysteresis: 3.5 mm still holds), and the force fades out.
  for (int i = 0; i < 5; ++i) tick(on.get(), {3.5, 0, -20});
  EXPECT_NEAR(rp::Norm(last), 0.6 * 3.5, 1e-12);
  const double beforeRelease = largest;
  for (int i = 0; i < 20; ++i) tick(on.get(), {4.2, 0, -20});
  EXPECT_NEAR(rp::Norm(last), 0, 1e-12);
  EXPECT_LE(largest, std::max(beforeRelease, step + 0.6 * 0.7 + 1e-12));  // the move itself, then the fade
  // A new snapshot that moves the axis by 1 mm (a dragged plan): fades from the old to the new.
  for (int i = 0; i < 20; ++i) tick(on.get(), {2.0, 0, -20});
  largest = 0;
  const auto moved = One(std::make_shared<rp::AxisGuidance>(7, "tunnel", Axis({1, 0, 0}, {1, 0, -50})), t);
  for (int i = 0; i < 20; ++i) tick(moved.get(), {2.0, 0, -20});
  EXPECT_NEAR(rp::Norm(last), 0.6 * 1.0, 1e-12);
  EXPECT_LE(largest, step + 1e-12);
}

TEST(FixtureRenderer, ATickWithAllFourFixturesDoesNotAllocate) {
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, {0, 0, -40});
  std::string error;
  auto set = std::make_unique<rp::FixtureSet>();
  ASSERT_TRUE(set->Add(std::make_shared<rp::AxisGuidance>(1, "axis", axis), Tuning(0.4, 0.001, 3, 4), true, error));
  ASSERT_TRUE(set->Add(std::make_shared<rp::DepthStop>(2, "depth", axis), Tuning(0.4, 0.001, 4, 4), true, error));
  ASSERT_TRUE(set->Add(std::shared_ptr<rp::VirtualFixture>(
                           rp::ForbiddenRegion::Make(3, "nerve", rp::shapes::Sphere({6, 0, -30}, 2, 3), 1, error)),
                       Tuning(0.4, 0.001, 2, 2), true, error));
  ASSERT_TRUE(set->Add(std::shared_ptr<rp::VirtualFixture>(rp::SurfaceConstraint::Mesh(
                           4, "bone", rp::shapes::Box({-10, -10, -60}, {10, 10, -5}), error)),
                       Tuning(0.2, 0.0, 1, 2), true, error));
  rp::FixtureRenderer r;
  r.Reset({0.5, 0, 10});
  const uint64_t before = rp::alloc::ThreadAllocations();
  for (int i = 0; i < 3000; ++i)
    r.Update(set.get(), {{0.5 * std::sin(0.01 * i), 0.2, 10 - 0.02 * i}, {0, 0, -1}, 1.0}, Period, Period);
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
}

// Inside the haptic renderer: the walls hold the tool before the tissue sees it, and the fixture's
// force goes through the passivity observer and the clamp with the tissue's.
TEST(FixturesInTheRenderer, TheDepthStopHoldsTheToolBeforeTheTissueAndTheClampKeepsTheSum) {
  const rp::MaterialTable table = rptest::Table(0.5, 0.001);
  auto scene = rptest::Scene({{"wall", "test", rptest::Quad({-50, -50, -30}, {50, -50, -30}, {50, 50, -30},
                                                             {-50, 50, -30}, {0, 0, 1})}},
                             table);
  const rp::TrajectoryAxis axis = Axis({0, 0, 0}, {0, 0, -20});  // stops 10 mm before the tissue
  const auto constraints =
      rp::MakeFixtureConstraints(One(std::make_shared<rp::DepthStop>(1, "stop", axis), Tuning(0.6, 0.001, 4, 4)));
  rp::HapticRenderer r;
  r.SetDevice(Omni());
  r.SetScene(scene.get());
  r.Reset(rptest::At({0, 0, 0}));
  for (int i = 1; i < 300; ++i) r.Update(rptest::At({0, 0, -35.0 * i / 300}), 0, constraints.get());
  const rp::RenderOutput& o = r.Update(rptest::At({0, 0, -35}), 0, constraints.get());  // the hand 5 mm into the tissue
  EXPECT_EQ(o.Contacts, 0);  // the tool was held at the stop
  EXPECT_NEAR(o.Points[0].Hip.z, -20, 1e-9);
  EXPECT_NEAR(o.Tip.z, -35, 1e-12);
  EXPECT_NEAR(rp::Norm(o.Force), std::min(0.6 * 15, Omni().MaxForce), 1e-9);  // clamped at 3.3 N
  EXPECT_TRUE(o.Clamped);
  EXPECT_GE(o.ObservedEnergy, -1e-9);
}

}  // namespace

namespace {

// The fixtures a plan drives: one per kind asked, ids stable across snapshots, clear errors.
TEST(PlanFixtures, BuiltFromAPlanSnapshotWithStableIdsAndClearErrors) {
  rp::PlanSnapshot plan;
  rp::TrajectorySnapshot t;
  t.NodeID = "vtkRPTrajectoryNode1";
  t.Name = "tibial tunnel";
  t.Entry = {0, 0, 0};
  t.Target = {0, 0, -30};
  plan.Trajectories.push_back(t);
  rp::StructureAtRiskSnapshot s;
  s.NodeID = "vtkRPModelNode2";
  s.Name = "popliteal vessels";
  s.SafetyMarginMm = 2;
  auto field = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  ASSERT_TRUE(field->Build(rp::shapes::Sphere({0, 15, -20}, 4, 3), error)) << error;
  s.Signed = field;
  plan.StructuresAtRisk.push_back(s);
  rp::PlanFixtureChoice choice;
  ASSERT_TRUE(rp::ParseFixtureKinds("axis,depth,forbidden", choice, error)) << error;
  const auto set = rp::BuildPlanFixtures(plan, choice, error);
  ASSERT_TRUE(set) << error;
  ASSERT_EQ(set->Count(), 3);
  EXPECT_EQ(set->Entries[0].Fixture->Kind(), rp::FixtureKind::AxisGuidance);
  EXPECT_EQ(set->Entries[1].Fixture->Kind(), rp::FixtureKind::DepthStop);
  EXPECT_EQ(set->Entries[2].Fixture->Kind(), rp::FixtureKind::ForbiddenRegion);
  EXPECT_EQ(rp::BuildPlanFixtures(plan, choice, error)->Entries[2].Fixture->Id(), set->Entries[2].Fixture->Id());
  EXPECT_FALSE(rp::ParseFixtureKinds("axis,wall", choice, error));
  EXPECT_NE(error.find("unknown fixture 'wall'"), std::string::npos) << error;
  choice.Trajectory = "screw";
  ASSERT_TRUE(rp::ParseFixtureKinds("axis", choice, error));
  EXPECT_FALSE(rp::BuildPlanFixtures(plan, choice, error));
  EXPECT_NE(error.find("no trajectory 'screw'"), std::string::npos) << error;
  plan.StructuresAtRisk[0].Signed = nullptr;
  choice.Trajectory.clear();
  ASSERT_TRUE(rp::ParseFixtureKinds("forbidden", choice, error));
  EXPECT_FALSE(rp::BuildPlanFixtures(plan, choice, error));
  EXPECT_NE(error.find("not a closed surface"), std::string::npos) << error;
}

}  // namespace
