// Haptic rendering against closed forms: plane, sphere, groove, corner, thin sheet, two tissues,
// clamp, friction cone, multi-point tool, stability limits, passivity observer, materials.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>

#include "rpDeviceProfiles.h"
#include "rpHapticsTestScenes.h"
#include "rpSimulatedDevice.h"

using rp::Vec3;
using rptest::At;
using rptest::MoveTo;

namespace {
rp::RendererOptions NoExtras() {
  rp::RendererOptions o;
  o.Friction = false;
  o.ForceShading = false;
  o.LimitGains = false;
  o.PassivityControl = false;
  return o;
}
double AngleDeg(const Vec3& a, const Vec3& b) {
  return std::acos(std::fmax(-1.0, std::fmin(1.0, rp::Dot(rp::Normalized(a), rp::Normalized(b))))) * 180.0 / M_PI;
}
constexpr double Gap = rp::GodObjectProxy::Gap;
}  // namespace

TEST(HapticRenderer, PlaneForceIsStiffnessTimesDepthAlongNormal) {
  const double k = 0.7;
  auto scene = rptest::Scene({{"floor", "test", rp::shapes::Box({-50, -50, -20}, {50, 50, 0})}}, rptest::Table(k, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  r.SetScene(scene.get());
  r.Reset(At({3, 4, 10}));
  for (double d : {0.5, 1.0, 2.5}) {
    MoveTo(r, {3, 4, 10}, {3, 4, -d}, 40);
    const rp::RenderOutput& out = r.Update(At({3, 4, -d}));  // at rest: no damping
    ASSERT_EQ(out.Contacts, 1);
    EXPECT_NEAR(out.Force.x, 0.0, 1e-9);
    EXPECT_NEAR(out.Force.y, 0.0, 1e-9);
    EXPECT_NEAR(out.Force.z, k * (d + Gap), 1e-9) << "depth " << d;
    EXPECT_NEAR(out.Points[0].Proxy.z, Gap, 1e-12);
    MoveTo(r, {3, 4, -d}, {3, 4, 10}, 40);
    EXPECT_EQ(r.Output().Contacts, 0);
    EXPECT_EQ(rp::Norm(r.Output().Force), 0.0);
  }
}

TEST(HapticRenderer, SphereForceDirectionErrorFallsWithTessellationAndShading) {
  const Vec3 c{0, 0, 0};
  const double radius = 20;
  double previousFlat = 1e9;
  for (int level = 1; level <= 4; ++level) {
    auto scene = rptest::Scene({{"ball", "test", rp::shapes::Sphere(c, radius, level)}}, rptest::Table(0.5, 0));
    double flatSum = 0, shadedSum = 0, shadedMax = 0;
    int samples = 0;
    for (int i = 0; i < 40; ++i) {
      // Directions spread over the sphere (golden spiral).
      const double z = 1 - 2 * (i + 0.5) / 40, phi = i * 2.399963;
      const Vec3 u{std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z};
      for (bool shading : {false, true}) {
        rp::HapticRenderer r;
        rp::RendererOptions o = NoExtras();
        o.ForceShading = shading;
        r.SetOptions(o);
        r.SetScene(scene.get());
        r.Reset(At(c + u * (radius + 5)));
        // 3 mm deep: below the flat facets of the coarsest level too (sagitta ~1.3 mm).
        MoveTo(r, c + u * (radius + 5), c + u * (radius - 3.0), 30);
        const rp::RenderOutput& out = r.Update(At(c + u * (radius - 3.0)));
        ASSERT_EQ(out.Contacts, 1) << "level " << level << " sample " << i;
        const double error = AngleDeg(out.Force, u);  // a true sphere pushes radially
        (shading ? shadedSum : flatSum) += error;
        if (shading) shadedMax = std::fmax(shadedMax, error);
      }
      ++samples;
    }
    const double flat = flatSum / samples, shaded = shadedSum / samples;
    std::cout << "sphere level " << level << " (" << scene->Mesh.Triangles.size() << " triangles): mean force "
              << "direction error flat " << flat << " deg, shaded " << shaded << " deg (max " << shadedMax << ")\n";
    // Flat facets: the error is about half the angle between neighbouring face normals.
    const double facetAngle = 63.4 / (1 << level);  // icosahedron dihedral step halves per level
    EXPECT_LT(flat, facetAngle) << "level " << level;
    EXPECT_LT(flat, previousFlat) << "level " << level;
    EXPECT_LT(shaded, 0.5 * flat) << "level " << level;
    if (level == 4) {
      EXPECT_LT(shadedMax, 1.0);
    }
    previousFlat = flat;
  }
}

TEST(HapticRenderer, GrooveHoldsTheProxyInTheCrease) {
  // V groove z >= |x|: wall A (x <= 0, normal (1,0,1)) and wall B (x >= 0, normal (-1,0,1)).
  const double k = 0.5;
  rp::TriangleMesh a = rptest::Quad({-20, -20, 20}, {0, -20, 0}, {0, 20, 0}, {-20, 20, 20}, {1, 0, 1});
  rp::TriangleMesh b = rptest::Quad({0, -20, 0}, {20, -20, 20}, {20, 20, 20}, {0, 20, 0}, {-1, 0, 1});
  auto scene = rptest::Scene({{"A", "test", a}, {"B", "test", b}}, rptest::Table(k, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  r.SetScene(scene.get());
  // On one wall only: the proxy is the projection onto that wall.
  r.Reset(At({5, 1, 10}));
  MoveTo(r, {5, 1, 10}, {5, 1, 3}, 40);
  const rp::RenderOutput& one = r.Update(At({5, 1, 3}));
  ASSERT_EQ(one.Points[0].Planes, 1);
  const Vec3 nB = rp::Normalized({-1, 0, 1});
  const double depth = -rp::Dot(Vec3{5, 1, 3}, nB);
  EXPECT_NEAR(rp::Norm(one.Force - nB * (k * (depth + Gap))), 0.0, 1e-9);
  // Below the crease: the god-object sits on the crease (closest feasible point).
  const Vec3 hip{0.5, 1, -2};
  MoveTo(r, {5, 1, 3}, hip, 60);
  const rp::RenderOutput& two = r.Update(At(hip));
  EXPECT_EQ(two.Points[0].Planes, 2);
  EXPECT_NEAR(two.Points[0].Proxy.x, 0.0, 1e-3);
  EXPECT_NEAR(two.Points[0].Proxy.z, Gap * std::sqrt(2.0), 1e-3);
  EXPECT_NEAR(two.Points[0].Proxy.y, 1.0, 1e-9);
  EXPECT_NEAR(rp::Norm(two.Force - (Vec3{0, 1, 0} - hip) * k), 0.0, 2e-3);
}

TEST(HapticRenderer, ThreePlaneCornerStopsTheProxyAtTheCorner) {
  const double k = 0.4;
  auto floor = rptest::Quad({0, 0, 0}, {20, 0, 0}, {20, 20, 0}, {0, 20, 0}, {0, 0, 1});
  auto wallX = rptest::Quad({0, 0, 0}, {0, 20, 0}, {0, 20, 20}, {0, 0, 20}, {1, 0, 0});
  auto wallY = rptest::Quad({0, 0, 0}, {20, 0, 0}, {20, 0, 20}, {0, 0, 20}, {0, 1, 0});
  auto scene = rptest::Scene({{"floor", "test", floor}, {"x", "test", wallX}, {"y", "test", wallY}}, rptest::Table(k, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  r.SetScene(scene.get());
  r.Reset(At({5, 5, 5}));
  const Vec3 hip{-1, -2, -3};
  MoveTo(r, {5, 5, 5}, hip, 80);
  const rp::RenderOutput& out = r.Update(At(hip));
  EXPECT_EQ(out.Points[0].Planes, 3);
  const Vec3 corner{Gap, Gap, Gap};
  EXPECT_NEAR(rp::Norm(out.Points[0].Proxy - corner), 0.0, 1e-6);
  EXPECT_NEAR(rp::Norm(out.Force - (corner - hip) * k), 0.0, 1e-6);
  // Never behind any wall on the way.
  EXPECT_GE(out.Points[0].Proxy.x, 0.0);
  EXPECT_GE(out.Points[0].Proxy.y, 0.0);
  EXPECT_GE(out.Points[0].Proxy.z, 0.0);
}

TEST(HapticRenderer, OneMillimetreSheetIsNotPoppedThroughAtHalfAMetrePerSecond) {
  const double k = 0.5;
  const rp::TriangleMesh sheet = rp::shapes::Box({-30, -30, -1}, {30, 30, 0});
  auto scene = rptest::Scene({{"sheet", "test", sheet}}, rptest::Table(k, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  r.SetScene(scene.get());
  // 500 mm/s at 1 kHz: 0.5 mm per tick, from 5 mm above to 6 mm below the sheet; also exactly
  // through the edge shared by the two top triangles (x = y) and along a slanted path.
  const Vec3 starts[3] = {{1.3, -2.1, 5}, {5, 5, 5}, {-7, 3, 5}};
  const Vec3 ends[3] = {{1.3, -2.1, -6}, {5, 5, -6}, {-2, 3, -6}};
  for (int run = 0; run < 3; ++run) {
    const Vec3 start = starts[run], end = ends[run];
    r.Reset(At(start));
    const int ticks = static_cast<int>(std::ceil(rp::Norm(end - start) / 0.5));
    double minProxyZ = 1e9;
    for (int i = 1; i <= ticks; ++i) {
      const Vec3 hip = start + (end - start) * (static_cast<double>(i) / ticks);
      const rp::RenderOutput& out = r.Update(At(hip));
      minProxyZ = std::fmin(minProxyZ, out.Points[0].Proxy.z);
      if (hip.z < 0) {
        ASSERT_EQ(out.Contacts, 1) << "run " << run << " hip z " << hip.z;
        EXPECT_GT(out.UnclampedForce.z, 0.0) << "force must push up at hip z " << hip.z;
      }
    }
    EXPECT_GE(minProxyZ, 0.0) << "run " << run;
    EXPECT_NEAR(r.Output().UnclampedForce.z, k * (6 + Gap), 1e-6) << "run " << run;
  }
  // The penalty method this replaces (nearest surface point) would push the hand down and out
  // of the sheet once past its middle: the test scene does expose pop-through.
  rp::ClosestPointHit nearest;
  ASSERT_TRUE(scene->Tree.ClosestPoint({1.3, -2.1, -0.75}, HUGE_VAL, nearest));
  EXPECT_NEAR(nearest.Point.z, -1.0, 1e-12);
}

TEST(HapticRenderer, TwoTissuesUseTheirOwnStiffness) {
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  const double kBone = table.Materials()[table.Find("bone")].Stiffness;
  const double kFat = table.Materials()[table.Find("fat")].Stiffness;
  auto scene = rptest::Scene({{"femur", "bone", rp::shapes::Box({-30, -10, -20}, {-10, 10, 0})},
                              {"pad", "fat", rp::shapes::Box({10, -10, -20}, {30, 10, 0})}},
                             table);
  rp::HapticRenderer r;
  rp::RendererOptions o;  // defaults: friction, shading, gain limits, passivity
  r.SetOptions(o);
  r.SetScene(scene.get());
  const double d = 1.2;
  double force[2];
  int label[2];
  for (int i = 0; i < 2; ++i) {
    const double x = i == 0 ? -20 : 20;
    r.Reset(At({x, 0, 10}));
    MoveTo(r, {x, 0, 10}, {x, 0, -d}, 100);
    for (int hold = 0; hold < 5; ++hold) r.Update(At({x, 0, -d}));
    force[i] = r.Output().Force.z;
    label[i] = r.Output().Points[0].Label;
  }
  EXPECT_EQ(table.Materials()[label[0]].Tissue, "bone");
  EXPECT_EQ(table.Materials()[label[1]].Tissue, "fat");
  EXPECT_NEAR(force[0], kBone * (d + Gap), 1e-6);
  EXPECT_NEAR(force[1], kFat * (d + Gap), 1e-6);
  EXPECT_NEAR(force[0] / force[1], kBone / kFat, 1e-6);
}

TEST(HapticRenderer, ClampKeepsTheDirection) {
  auto floor = rptest::Quad({0, 0, 0}, {20, 0, 0}, {20, 20, 0}, {0, 20, 0}, {0, 0, 1});
  auto wallX = rptest::Quad({0, 0, 0}, {0, 20, 0}, {0, 20, 20}, {0, 0, 20}, {1, 0, 0});
  auto wallY = rptest::Quad({0, 0, 0}, {20, 0, 0}, {20, 0, 20}, {0, 0, 20}, {0, 1, 0});
  auto scene = rptest::Scene({{"floor", "test", floor}, {"x", "test", wallX}, {"y", "test", wallY}}, rptest::Table(2.0, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  rp::DeviceInfo device;
  device.MaxForce = 3.3;
  r.SetDevice(device);
  r.SetScene(scene.get());
  r.Reset(At({5, 5, 5}));
  const Vec3 hip{-1, -2, -3};
  MoveTo(r, {5, 5, 5}, hip, 80);
  const rp::RenderOutput& out = r.Update(At(hip));
  EXPECT_TRUE(out.Clamped);
  EXPECT_NEAR(rp::Norm(out.UnclampedForce), 2.0 * std::sqrt(14.0), 1e-3);
  EXPECT_NEAR(rp::Norm(out.Force), 3.3, 1e-12);
  EXPECT_LT(AngleDeg(out.Force, out.UnclampedForce), 1e-6);
  // Below the threshold nothing changes.
  MoveTo(r, hip, {5, 5, -0.5}, 80);
  const rp::RenderOutput& small = r.Update(At({5, 5, -0.5}));
  EXPECT_FALSE(small.Clamped);
  EXPECT_NEAR(small.Force.z, 2.0 * (0.5 + Gap), 1e-9);
}

TEST(HapticRenderer, FrictionConeStaticThenDynamic) {
  const double k = 1.0, mus = 0.5, mud = 0.3, d = 1.0;
  auto scene = rptest::Scene({{"floor", "test", rp::shapes::Box({-50, -50, -20}, {50, 50, 0})}},
                             rptest::Table(k, 0, mus, mud));
  rp::HapticRenderer r;
  rp::RendererOptions o = NoExtras();
  o.Friction = true;
  r.SetOptions(o);
  r.SetScene(scene.get());
  r.Reset(At({0, 0, 5}));
  MoveTo(r, {0, 0, 5}, {0, 0, -d}, 50);
  const double normal = k * (d + Gap);
  // Inside the static cone (tangential/normal < 0.5): the proxy does not move.
  for (double x = 0.01; x <= 0.45; x += 0.01) {
    const rp::RenderOutput& out = r.Update(At({x, 0, -d}));
    EXPECT_NEAR(out.Points[0].Proxy.x, 0.0, 1e-12) << "x " << x;
    EXPECT_NEAR(-out.Force.x / out.Force.z, x / (d + Gap), 1e-9);
  }
  // Past it: sliding, the proxy trails by mu_d * depth.
  double ratio = 0;
  for (double x = 0.46; x <= 3.0; x += 0.01) {
    const rp::RenderOutput& out = r.Update(At({x, 0, -d}));
    ratio = -out.Force.x / out.Force.z;
    EXPECT_LE(ratio, mus + 1e-9);
  }
  EXPECT_NEAR(ratio, mud, 1e-6);
  EXPECT_NEAR(r.Output().Force.z, normal, 1e-9);
  EXPECT_NEAR(r.Output().Points[0].Proxy.x, 3.0 - mud * (d + Gap), 0.011);
}

TEST(HapticRenderer, MultiPointToolSumsContactForces) {
  // Shaft along +x from the tip, tilted: the tip 1 mm deep, the next point 0.4 mm deep, the
  // third 0.2 mm above the floor. Eq. 4: F = sum of k d_i over the points in contact.
  const double k = 0.08;
  auto scene = rptest::Scene({{"floor", "test", rp::shapes::Box({-50, -50, -20}, {50, 50, 0})}}, rptest::Table(k, 0));
  rp::HapticRenderer r;
  r.SetOptions(NoExtras());
  const Vec3 points[3] = {{0, 0, 0}, {10, 0, 0}, {20, 0, 0}};
  ASSERT_TRUE(r.SetToolPoints(points, 3));
  r.SetScene(scene.get());
  // Rotation about y tilting the shaft so point i is at depth 1 - 0.04*10*i... use sin(a)=0.03.
  const double s = 0.06, c = std::sqrt(1 - s * s);
  rp::Pose pose;
  pose.R[0] = c; pose.R[2] = -s; pose.R[6] = s; pose.R[8] = c;  // x' = c x, z' = s x: the shaft rises
  rp::Pose above = pose;
  above.T = {0, 0, 5};
  r.Reset(above);
  for (int i = 1; i <= 60; ++i) {
    rp::Pose p = pose;
    p.T = {0, 0, 5 - 6.0 * i / 60};  // tip ends 1 mm deep
    r.Update(p);
  }
  pose.T = {0, 0, -1};
  const rp::RenderOutput& out = r.Update(pose);
  ASSERT_EQ(out.Contacts, 2);  // depths 1 and 0.4 mm; the third point is 0.2 mm above
  const double expected = k * ((1 + Gap) + (1 - 10 * s + Gap));
  EXPECT_NEAR(out.Force.z, expected, 1e-9);
  EXPECT_FALSE(out.Points[2].InContact);
}

TEST(HapticRenderer, SummedContactsStayInsideTheStabilityLimit) {
  auto scene = rptest::Scene({{"floor", "bone", rp::shapes::Box({-50, -50, -20}, {50, 50, 0})}},
                             rp::MaterialTable::Defaults());
  rp::HapticRenderer r;
  rp::RendererOptions o = NoExtras();
  o.LimitGains = true;
  r.SetOptions(o);
  rp::DeviceProfile omni;
  std::string error;
  ASSERT_TRUE(rp::FindDeviceProfile("omni", omni, error)) << error;
  r.SetDevice(omni.Info);  // nominal 0.7 N/mm
  const Vec3 points[3] = {{0, 0, 0}, {10, 0, 0}, {20, 0, 0}};  // flat on the floor
  r.SetToolPoints(points, 3);
  r.SetScene(scene.get());
  r.Reset(At({0, 0, 5}));
  MoveTo(r, {0, 0, 5}, {0, 0, -0.4}, 50);
  const rp::RenderOutput& out = r.Update(At({0, 0, -0.4}));
  ASSERT_EQ(out.Contacts, 3);
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  const double kBone = table.Materials()[static_cast<size_t>(table.Find("bone"))].Stiffness;
  ASSERT_GT(3 * kBone, 0.7);
  EXPECT_NEAR(out.Gains.Stiffness, 0.7, 1e-12);  // 3 x bone summed, capped at the Omni's 0.7 N/mm
  EXPECT_NEAR(out.Force.z, 0.7 * (0.4 + Gap), 1e-9);
  EXPECT_GE(out.Gains.Margin, 0.0);
}

TEST(Stability, ColgateSchenkelLimits) {
  rp::DeviceInfo device;
  device.PhysicalDamping = 0.002;
  device.NominalMaxStiffness = 10;
  device.NominalMaxDamping = 0.005;
  // b > KT/2 + |B|: with B = 0.001 (half the budget), K <= 2 (0.002 - 0.001) / 0.001 = 2.
  EXPECT_NEAR(rp::PassiveStiffnessLimit(device, 0.001, 0.001), 2.0, 1e-12);
  EXPECT_NEAR(rp::PassiveStiffnessLimit(device, 0.001, 0.0), 4.0, 1e-12);
  EXPECT_EQ(rp::PassiveStiffnessLimit(device, 0.001, 0.003), 0.0);
  rp::GainLimits g = rp::LimitGains(6, 0.004, device, 0.001);
  const double f = rp::PassiveSafetyFraction;
  EXPECT_NEAR(g.Damping, 0.001, 1e-15);
  EXPECT_NEAR(g.Stiffness, 2.0 * f, 1e-12);
  EXPECT_NEAR(g.StiffnessScale, 2.0 * f / 6, 1e-12);
  EXPECT_NEAR(g.DampingScale, 0.25, 1e-12);
  EXPECT_NEAR(g.Margin, 0.002 - (2.0 * f * 0.0005 + 0.001), 1e-15);
  EXPECT_GT(g.Margin, 0.0);
  // Slower servo: half the rate halves the passive stiffness.
  EXPECT_NEAR(rp::LimitGains(6, 0.004, device, 0.002).Stiffness, 1.0 * f, 1e-12);
  // Workspace scaling multiplies the stiffness the device feels.
  g = rp::LimitGains(1.5, 0, device, 0.001, 2.0);
  EXPECT_NEAR(g.Stiffness, 3.0, 1e-12);
  EXPECT_NEAR(g.StiffnessScale, 1.0, 1e-12);
  g = rp::LimitGains(3, 0, device, 0.001, 2.0);
  EXPECT_NEAR(g.StiffnessScale, 4.0 * f / 6.0, 1e-12);
  EXPECT_GT(rp::LimitGains(1, 0, device, 0.001).Margin, 0.0);
}

TEST(PassivityObserver, SampledWallCreatesEnergyAndTheControllerRemovesIt) {
  // A wall sampled with a zero-order hold returns more energy than it took: over an in-out
  // stroke of n equal steps s each way, E = -k n s^2 exactly (held force k s j_(i-1)).
  const double k = 2.0, step = 0.05;
  const int n = 40;  // 2 mm deep
  auto run = [&](bool control) {
    rp::PassivityObserver po(1.0);
    po.Reset({0, 0, 0});
    double worst = 0;
    for (int i = 1; i <= 2 * n + 1; ++i) {
      const int j = i <= n ? i : std::max(0, 2 * n - i);
      const Vec3 x{0, 0, -step * j};
      po.Observe(x);
      Vec3 f{0, 0, k * step * j};
      const Vec3 v = (i <= n ? Vec3{0, 0, -step} : Vec3{0, 0, step}) / 0.001;
      if (control) f = po.Correct(v, f, 0.001);
      po.Held(f);
      worst = std::fmin(worst, po.ObservedEnergy());
    }
    return std::make_pair(po.ObservedEnergy(), worst);
  };
  const auto open = run(false);
  EXPECT_NEAR(open.first, -k * n * step * step, 1e-9);
  const auto closed = run(true);
  // The deficit first appears at depth j with j(j+1)/2 < n; the controller removes it within a
  // step, so it never exceeds one step's worth, k s^2 (sqrt(2n) + 1), and ends at most k s^2.
  EXPECT_GT(closed.second, -k * step * step * (std::sqrt(2.0 * n) + 1));
  EXPECT_GE(closed.first, -k * step * step * 1.0001);
  EXPECT_LT(std::fabs(closed.first), 0.05 * std::fabs(open.first));
}

TEST(Materials, LoadTheResourceTableAndReportBadFiles) {
  rp::MaterialTable table;
  std::string error;
  ASSERT_TRUE(table.Load(std::string(ROBOPLAN_RESOURCES_DIR) + "/Materials/materials.json", error)) << error;
  for (const char* tissue : {"bone", "cartilage", "ligament", "tendon", "muscle", "fat", "skin"})
    EXPECT_GE(table.Find(tissue), 0) << tissue;
  EXPECT_EQ(table.Materials()[table.DefaultIndex()].Tissue, "muscle");
  // The built-in table is the resource file compiled in: they agree field by field.
  const rp::MaterialTable defaults = rp::MaterialTable::Defaults();
  ASSERT_EQ(defaults.Materials().size(), table.Materials().size());
  EXPECT_NE(defaults.Source().find("built-in"), std::string::npos) << defaults.Source();
  EXPECT_EQ(defaults.TissueNames(), table.TissueNames());
  for (const auto& m : defaults.Materials()) {
    const auto& f = table.Materials()[table.Find(m.Tissue)];
    EXPECT_EQ(f.Stiffness, m.Stiffness) << m.Tissue;
    EXPECT_EQ(f.Damping, m.Damping) << m.Tissue;
    EXPECT_EQ(f.StaticFriction, m.StaticFriction) << m.Tissue;
    EXPECT_EQ(f.DynamicFriction, m.DynamicFriction) << m.Tissue;
  }
  // Stiffness order follows the tissues' moduli.
  auto k = [&](const char* t) { return table.Materials()[table.Find(t)].Stiffness; };
  EXPECT_GT(k("bone"), k("cartilage"));
  EXPECT_GT(k("cartilage"), k("skin"));
  EXPECT_GT(k("skin"), k("fat"));

  const std::string dir = ROBOPLAN_TEST_OUTPUT_DIR;
  std::string cmd = "mkdir -p '" + dir + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string bad = dir + "/bad.json";
  std::ofstream(bad) << R"({"materials": [{"tissue": "bone", "stiffness": -1, "damping": 0}]})";
  rp::MaterialTable kept = table;
  EXPECT_FALSE(kept.Load(bad, error));
  EXPECT_NE(error.find("stiffness"), std::string::npos) << error;
  EXPECT_EQ(kept.Materials().size(), table.Materials().size());  // nothing lost
  std::ofstream(bad) << "{ not json";
  EXPECT_FALSE(kept.Load(bad, error));
  EXPECT_NE(error.find("not valid JSON"), std::string::npos) << error;
  EXPECT_FALSE(kept.Load(dir + "/missing.json", error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  std::ofstream(bad) << R"({"materials": [{"tissue": "bone", "stiffness": 1, "damping": 0},
                                           {"tissue": "Bone", "stiffness": 2, "damping": 0}]})";
  EXPECT_FALSE(kept.Load(bad, error));
  EXPECT_NE(error.find("listed twice"), std::string::npos) << error;
}

TEST(Materials, OneLoaderFindsTheResourceFileAndFallsBackOnlyWhenItIsAbsent) {
  // The function every program uses: Resources/Materials/materials.json through ResourcePath.
  rp::MaterialTable table;
  std::string error;
  ASSERT_TRUE(rp::LoadMaterialTable(table, error)) << error;
  EXPECT_NE(table.Source().find("Materials/materials.json"), std::string::npos) << table.Source();
  EXPECT_EQ(table.Source().find("built-in"), std::string::npos) << table.Source();
  // Resources moved away: the same file, compiled in, and Source() says so.
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/no-resources";
  ASSERT_EQ(std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str()), 0);
  const char* previous = std::getenv("ROBOPLAN_RESOURCES_DIR");
  const std::string restore = previous ? previous : "";
  ASSERT_EQ(setenv("ROBOPLAN_RESOURCES_DIR", dir.c_str(), 1), 0);
  rp::MaterialTable fallback;
  EXPECT_TRUE(rp::LoadMaterialTable(fallback, error)) << error;
  EXPECT_NE(fallback.Source().find("built-in"), std::string::npos) << fallback.Source();
  EXPECT_EQ(fallback.TissueNames(), table.TissueNames());
  // A table there that is broken is an error naming it, never replaced by the built-in one.
  ASSERT_EQ(std::system(("mkdir -p '" + dir + "/Materials'").c_str()), 0);
  std::ofstream(dir + "/Materials/materials.json") << R"({"materials": []})";
  rp::MaterialTable broken;
  EXPECT_FALSE(rp::LoadMaterialTable(broken, error));
  EXPECT_NE(error.find("lists no materials"), std::string::npos) << error;
  if (restore.empty())
    unsetenv("ROBOPLAN_RESOURCES_DIR");
  else
    setenv("ROBOPLAN_RESOURCES_DIR", restore.c_str(), 1);
}

TEST(DeviceProfiles, OmniAndTouchByNameWithTheirLimits) {
  rp::DeviceProfile p;
  std::string error;
  ASSERT_TRUE(rp::FindDeviceProfile("omni", p, error)) << error;
  EXPECT_EQ(p.Key, rp::DeviceProfiles().front().Key);  // the default: the seed paper's device
  EXPECT_DOUBLE_EQ(p.Info.MaxForce, 3.3);
  EXPECT_DOUBLE_EQ(p.Info.NominalMaxStiffness, 0.7);
  EXPECT_DOUBLE_EQ(p.Info.WorkspaceMax.x - p.Info.WorkspaceMin.x, 160);
  EXPECT_DOUBLE_EQ(p.Info.WorkspaceMax.y - p.Info.WorkspaceMin.y, 120);
  EXPECT_DOUBLE_EQ(p.Info.WorkspaceMax.z - p.Info.WorkspaceMin.z, 70);
  ASSERT_TRUE(rp::FindDeviceProfile("TOUCH", p, error)) << error;
  EXPECT_DOUBLE_EQ(p.Info.MaxForce, 3.3);
  EXPECT_DOUBLE_EQ(p.Info.NominalMaxStiffness, 0.4);
  ASSERT_TRUE(rp::FindDeviceProfile(p.Info.Name, p, error)) << error;  // the display name works too
  EXPECT_FALSE(rp::FindDeviceProfile("falcon", p, error));
  EXPECT_NE(error.find("omni|touch"), std::string::npos) << error;
  EXPECT_EQ(rp::SimulatedDevice::DefaultInfo().NominalMaxStiffness, 0.7);
}

TEST(DeviceProfiles, TissuesAboveTheDeviceAndTheMeasuredPeriodAreClampedWithAWarning) {
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  rp::DeviceProfile omni, touch;
  std::string error;
  ASSERT_TRUE(rp::FindDeviceProfile("omni", omni, error));
  ASSERT_TRUE(rp::FindDeviceProfile("touch", touch, error));
  // The Omni renders the whole table at 1 kHz (bone sits at its nominal maximum).
  for (const rp::MaterialClamp& c : rp::ClampMaterials(table.Materials(), omni.Info, 0.001)) {
    EXPECT_FALSE(c.Clamped()) << c.Tissue;
    EXPECT_DOUBLE_EQ(c.RenderedStiffness, c.RequestedStiffness) << c.Tissue;
  }
  // The Touch: every tissue above 0.4 N/mm is rendered at 0.4, the others as asked.
  int clamped = 0;
  for (const rp::MaterialClamp& c : rp::ClampMaterials(table.Materials(), touch.Info, 0.001)) {
    EXPECT_NEAR(c.RenderedStiffness, std::min(c.RequestedStiffness, 0.4), 1e-12) << c.Tissue;
    EXPECT_EQ(c.Clamped(), c.RequestedStiffness > 0.4) << c.Tissue;
    if (!c.Clamped()) continue;
    ++clamped;
    const std::string warning = rp::ClampWarning(c, touch.Info);
    EXPECT_EQ(warning.rfind(c.Tissue + ": stiffness", 0), 0u) << warning;
    EXPECT_NE(warning.find("nominal maximum 0.40"), std::string::npos) << warning;
    EXPECT_NE(warning.find("rendered at 0.40 N/mm"), std::string::npos) << warning;
  }
  int above = 0;  // every tissue of the table above the Touch's 0.4 N/mm
  for (const rp::Material& m : table.Materials()) above += m.Stiffness > 0.4;
  EXPECT_EQ(clamped, above);
  // A servo loop that only keeps 10 ms: Colgate-Schenkel K < 2 (b - B) / T binds below the
  // nominal limit: 0.9 * 2 * (0.003 - 0.001) / 0.010 = 0.36 N/mm for bone (b = 0.001 N·s/mm).
  const auto slow = rp::ClampMaterials(table.Materials(), omni.Info, 0.010);
  const rp::MaterialClamp& bone = slow[static_cast<size_t>(table.Find("bone"))];
  const double bBone = std::min(table.Materials()[static_cast<size_t>(table.Find("bone"))].Damping, 0.0015);
  EXPECT_NEAR(bone.RenderedStiffness, 0.9 * 2 * (0.003 - bBone) / 0.010, 1e-12);
  EXPECT_NE(bone.Limit.find("passivity"), std::string::npos) << bone.Limit;
  EXPECT_NE(bone.Limit.find("10.00 ms"), std::string::npos) << bone.Limit;
}

TEST(HapticScene, UnknownTissueFallsBackAndBadMeshIsRefused) {
  std::vector<std::string> warnings;
  std::string error;
  auto scene = rp::HapticScene::Build({{"mystery", "unobtainium", rp::shapes::Box({0, 0, 0}, {1, 1, 1})}},
                                      rp::MaterialTable::Defaults(), warnings, error);
  ASSERT_TRUE(scene);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("unobtainium"), std::string::npos);
  EXPECT_EQ(scene->MaterialOf(0).Tissue, "muscle");
  rp::TriangleMesh broken = rp::shapes::Box({0, 0, 0}, {1, 1, 1});
  broken.Triangles[0][0] = 1000;
  EXPECT_FALSE(rp::HapticScene::Build({{"broken", "bone", broken}}, rp::MaterialTable::Defaults(), warnings, error));
  EXPECT_NE(error.find("broken"), std::string::npos) << error;
}
