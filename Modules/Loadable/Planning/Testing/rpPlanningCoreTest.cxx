// The plan's figures against closed forms: a tool through an analytic bone (a square tube of known
// wall thickness) gives the known length in bone and breach; the clearance to a sphere is its
// closed form (up to the sphere mesh's own flats, measured); the HU profile through a volume with
// a known ramp is exact; cut volumes of a box are exact and of a sphere the cap's; the proposal on
// a scene whose best entry is known analytically finds it within the candidate spacing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rpAllocationCounter.h"
#include "rpCutFigures.h"
#include "rpScrewMesh.h"
#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"

namespace {

constexpr double Pi = 3.14159265358979323846;

// A volume of float voxels with spacing h, origin `lo`, filled by f(x, y, z) at the voxel centres.
struct AnalyticVolume {
  std::vector<float> Voxels;
  int Dims[3];
  double IjkToRas[16];
  template <class F>
  AnalyticVolume(const rp::Vec3& lo, const rp::Vec3& hi, double h, F&& f) {
    for (int a = 0; a < 3; ++a) this->Dims[a] = static_cast<int>(std::round((hi[a] - lo[a]) / h)) + 1;
    const double m[16] = {h, 0, 0, lo.x, 0, h, 0, lo.y, 0, 0, h, lo.z, 0, 0, 0, 1};
    std::copy(m, m + 16, this->IjkToRas);
    this->Voxels.resize(static_cast<size_t>(this->Dims[0]) * this->Dims[1] * this->Dims[2]);
    size_t n = 0;
    for (int k = 0; k < this->Dims[2]; ++k)
      for (int j = 0; j < this->Dims[1]; ++j)
        for (int i = 0; i < this->Dims[0]; ++i) this->Voxels[n++] = static_cast<float>(f(lo.x + i * h, lo.y + j * h, lo.z + k * h));
  }
  void Into(rp::VolumeSampler& sampler) const {
    std::string error;
    ASSERT_TRUE(sampler.Set(this->Voxels.data(), rp::VoxelType::Float32, this->Dims, this->IjkToRas, error)) << error;
  }
};

// The materials' bone ranges: cortical ("bone") from 600 HU, cancellous ("trabecular bone") 100-600.
void AddBoneRanges(rp::TissueModel& tissue) {
  tissue.BoneRanges = {{"bone", 600, HUGE_VAL}, {"trabecular bone", 100, 600}};
  tissue.BoneThresholdHU = 100;
}

// A square tube along S: bone where max(|R|, |A|) lies in [6, 10] (walls 4 mm thick). The CT is
// 1000 HU in the wall, -1000 HU out of it, with a linear ramp 2 mm wide centred on each wall face:
// trilinear sampling is exact on the ramp, so the 100 HU bone threshold crosses exactly where
// 100 = 1000 * (signed distance into the wall) / 1 mm... placed on the faces themselves.
double TubeHU(double x, double y, double) {
  const double m = std::max(std::fabs(x), std::fabs(y));
  const double into = std::min(m - 6, 10 - m);  // signed distance into the wall (mm)
  return std::clamp(100 + 900 * into, -1000.0, 1000.0);
}

rp::TrajectorySnapshot Trajectory(const rp::Vec3& entry, const rp::Vec3& target, double diameter) {
  rp::TrajectorySnapshot t;
  t.Name = "test";
  t.Entry = entry, t.Target = target, t.ToolDiameterMm = diameter;
  return t;
}

rp::StructureAtRiskSnapshot Structure(const std::string& name, const rp::TriangleMesh& mesh, double margin) {
  rp::StructureAtRiskSnapshot s;
  s.Name = name;
  s.SafetyMarginMm = margin;
  auto surface = std::make_shared<rp::TriangleMesh>(mesh);
  surface->ComputeNormals();
  s.Surface = surface;
  auto tree = std::make_shared<rp::BVH>();
  tree->Build(*surface);
  s.Tree = tree;
  auto signedDistance = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  EXPECT_TRUE(signedDistance->Build(*surface, error)) << error;
  s.Signed = signedDistance;
  return s;
}

// How far an icosphere's flats lie inside the true sphere: the tolerance of a "sphere" test.
double Flatness(const rp::TriangleMesh& mesh, const rp::Vec3& center, double radius) {
  double worst = 0;
  for (const auto& t : mesh.Triangles) {
    double bary[3];
    const rp::Vec3 q = rp::BVH::ClosestPointOnTriangle(center, mesh.Points[t[0]], mesh.Points[t[1]], mesh.Points[t[2]], bary);
    worst = std::max(worst, radius - rp::Norm(q - center));
  }
  return worst;
}

}  // namespace

// The Gertzbein-Robbins grade is rpExecutionScore.h's (tested in rpExecutionScoreTest).

TEST(PlanningCore, ATunnelAcrossATubeHasTheWallsLengthInBoneAndNoBreach) {
  const AnalyticVolume ct({-14, -14, -3}, {14, 14, 3}, 0.5, TubeHU);
  rp::TissueModel tissue;
  ct.Into(tissue.CT);
  AddBoneRanges(tissue);
  tissue.Prepare();
  // Along R through the tube's axis: through both walls (4 mm each) and the canal between.
  const rp::TrajectorySnapshot across = Trajectory({-13, 0, 0}, {13, 0, 0}, 2.0);
  const rp::TrajectoryFigures f = rp::ComputeTrajectoryFigures(across, tissue, {});
  EXPECT_DOUBLE_EQ(f.LengthMm, 26);
  EXPECT_NEAR(f.LengthInBoneMm, 8, 1e-6);
  ASSERT_EQ(f.Bone.size(), 2u);
  EXPECT_NEAR(f.Bone[0].FromMm, 3, 1e-6);  // depth from the entry at R = -13
  EXPECT_NEAR(f.Bone[0].ToMm, 7, 1e-6);
  EXPECT_NEAR(f.Bone[1].FromMm, 19, 1e-6);
  EXPECT_NEAR(f.Bone[1].ToMm, 23, 1e-6);
  EXPECT_FALSE(f.Breach.Found);  // perpendicular through the walls: no footprint, no breach
  // Cortical (>= 600 HU) in each wall where 100 + 900 d >= 600: d >= 5/9 mm from each face.
  ASSERT_EQ(f.BoneByHU.size(), 2u);
  EXPECT_NEAR(f.BoneByHU[0].LengthMm, 2 * (4 - 2 * 5.0 / 9), 0.26);  // tissue steps of 0.125 mm
  EXPECT_NEAR(f.BoneByHU[0].LengthMm + f.BoneByHU[1].LengthMm, 8, 0.26);
}

TEST(PlanningCore, AToolAlongTheWallBreachesByHowFarItStandsOut) {
  const AnalyticVolume ct({-14, -14, -12}, {14, 14, 12}, 0.5, TubeHU);
  rp::TissueModel tissue;
  ct.Into(tissue.CT);
  AddBoneRanges(tissue);
  tissue.Prepare();
  // A tool along S in the wall stands out of it by how far its surface passes a face: a 6 mm tool
  // 0.8 mm inside the outer face by 2.2 mm (grade 2); on the wall's middle (R = 8) by 1 mm on both
  // sides (grade 1); at R = 7.5 by 1.5 mm into the canal (grade 1); a 12 mm tool at R = 9 by 5 mm
  // (grade 3).
  const struct {
    double x, diameter, breach;
    int grade;
  } cases[] = {{9.2, 6, 2.2, 2}, {8.0, 6, 1.0, 1}, {7.5, 6, 1.5, 1}, {9.0, 12, 5.0, 3}};
  for (const auto& c : cases) {
    const rp::TrajectoryFigures f =
        rp::ComputeTrajectoryFigures(Trajectory({c.x, 0, -10}, {c.x, 0, 10}, c.diameter), tissue, {});
    EXPECT_NEAR(f.LengthInBoneMm, 20, 1e-9) << c.x;
    ASSERT_TRUE(f.Breach.Found) << c.x;
    EXPECT_NEAR(f.Breach.BreachMm, c.breach, 1e-6) << c.x;
    EXPECT_EQ(f.Breach.Grade, c.grade) << c.x;
  }
  // A 3.9 mm tool on the wall's middle stays inside: no breach.
  EXPECT_FALSE(rp::ComputeTrajectoryFigures(Trajectory({8, 0, -10}, {8, 0, 10}, 3.9), tissue, {}).Breach.Found);
}

// A ball of bone (radius 15, the 100 HU threshold on its surface, 1000 HU inside): a tool that
// enters it is no breach, wherever its entry lies (on the surface, as a proposed entry does, or
// outside) and however the surface curves away from it; a tool along a chord near the surface
// stands out of it by the closed form.
double BallHU(double x, double y, double z) { return std::clamp(100 + 900 * (15 - std::sqrt(x * x + y * y + z * z)), -1000.0, 1000.0); }

TEST(PlanningCore, EnteringACurvedBoneIsNoBreachWhereverTheEntryLies) {
  const AnalyticVolume ct({-20, -20, -20}, {20, 20, 22}, 0.5, BallHU);
  rp::TissueModel tissue;
  ct.Into(tissue.CT);
  AddBoneRanges(tissue);
  tissue.Prepare();
  for (const double entryZ : {15.0, 15.02, 18.0}) {  // on the surface, a hair outside, outside
    const rp::TrajectoryFigures f = rp::ComputeTrajectoryFigures(Trajectory({0, 0, entryZ}, {0, 0, 0}, 4.0), tissue, {});
    EXPECT_NEAR(f.LengthInBoneMm, 15, 1e-3) << entryZ;
    EXPECT_FALSE(f.Breach.Found) << entryZ << ": " << f.Breach.BreachMm << " mm at " << f.Breach.DepthMm;
  }
  // Oblique, entry on the surface: from (0, 9, 12) (|p| = 15) to the centre.
  EXPECT_FALSE(rp::ComputeTrajectoryFigures(Trajectory({0, 9, 12}, {0, 0, 0}, 4.0), tissue, {}).Breach.Found);
  // Along a chord 14 mm from the centre (z from 8 to -8): the 4 mm tool's surface stands out by
  // 2 - (15 - 14) = 1 mm where the chord is deepest (z = 0).
  const rp::TrajectoryFigures chord = rp::ComputeTrajectoryFigures(Trajectory({14, 0, 8}, {14, 0, -8}, 4.0), tissue, {});
  ASSERT_TRUE(chord.Breach.Found);
  EXPECT_NEAR(chord.Breach.BreachMm, 1.0, 0.01);
  EXPECT_NEAR(chord.Breach.DepthMm, 8, 0.5);
}

TEST(PlanningCore, TheProfileOfALinearRampIsExact) {
  // HU = 5 R - 3 A + 2 S + 40: trilinear sampling reproduces it anywhere inside the grid.
  auto ramp = [](double x, double y, double z) { return 5 * x - 3 * y + 2 * z + 40; };
  const AnalyticVolume ct({-20, -20, -20}, {20, 20, 20}, 1.0, ramp);
  rp::TissueModel tissue;
  ct.Into(tissue.CT);
  AddBoneRanges(tissue);
  tissue.Prepare();
  const rp::Vec3 entry{-8, 5, -11}, target{9, -6, 12};
  const rp::TrajectoryFigures f = rp::ComputeTrajectoryFigures(Trajectory(entry, target, 4.0), tissue, {});
  ASSERT_GT(f.Profile.size(), 50u);
  const rp::Vec3 u = rp::Normalized(target - entry);
  const rp::Vec3 g{5, -3, 2};
  const double across = 2.0 * rp::Norm(g - u * rp::Dot(g, u));  // the ramp's rise across the tool's radius
  for (const auto& s : f.Profile) {
    const rp::Vec3 p = entry + u * s.DepthMm;
    EXPECT_NEAR(s.HU, ramp(p.x, p.y, p.z), 1e-9);
    EXPECT_NEAR(s.MeanHU, s.HU, 1e-9);  // symmetric rings: the mean of a linear field is the axis value
    EXPECT_LE(s.MaxHU, s.HU + across + 1e-9);
    EXPECT_GE(s.MinHU, s.HU - across - 1e-9);
    EXPECT_GT(s.MaxHU, s.HU + 0.8 * across);  // the outer ring reaches most of it
  }
  EXPECT_NEAR(f.Profile.back().DepthMm, rp::Norm(target - entry), 1e-12);
}

TEST(PlanningCore, ClearanceFromASphereIsItsClosedForm) {
  const rp::Vec3 c{2, -3, 40};
  const double R = 8;
  const rp::TriangleMesh sphere = rp::shapes::Sphere(c, R, 6);
  const double flat = Flatness(sphere, c, R);
  ASSERT_LT(flat, 0.002);
  const std::vector<rp::StructureAtRiskSnapshot> structures = {Structure("vessel", sphere, 2.0)};
  rp::TissueModel none;
  none.Prepare();
  // Axis along S at distance h from the centre's line: clearance h - R - r, closest at the
  // centre's height.
  for (double h : {9.0, 11.0, 15.0}) {
    const rp::TrajectoryFigures f =
        rp::ComputeTrajectoryFigures(Trajectory({c.x + h, c.y, 0}, {c.x + h, c.y, 80}, 3.0), none, structures);
    ASSERT_EQ(f.Clearances.size(), 1u);
    const rp::ClearanceFigure& k = f.Clearances[0];
    EXPECT_LE(k.ClearanceMm, h - R - 1.5 + flat + 1e-9);
    EXPECT_GE(k.ClearanceMm, h - R - 1.5 - 1e-9);
    EXPECT_NEAR(k.DepthMm, 40, 0.5);
    EXPECT_EQ(k.UnderMargin, h - R - 1.5 < 2.0);
    EXPECT_FALSE(k.Crosses);
  }
  // An axis through the centre enters it by R: clearance -(r + R).
  const rp::TrajectoryFigures through = rp::ComputeTrajectoryFigures(Trajectory({c.x, c.y, 0}, {c.x, c.y, 80}, 3.0), none, structures);
  EXPECT_TRUE(through.Clearances[0].Crosses);
  EXPECT_NEAR(through.Clearances[0].ClearanceMm, -1.5 - R, flat + 0.01);
  EXPECT_NEAR(through.Clearances[0].DepthMm, 40, 0.5);
}

TEST(PlanningCore, CutVolumesAndAreaAreExactForABoxAndTheCapForASphere) {
  const rp::TriangleMesh box = rp::shapes::Box({0, 0, 0}, {10, 20, 30});
  const rp::CutFigures f = rp::CutBone(box, {3, 7, 11}, {1, 0, 0});
  EXPECT_NEAR(f.VolumeMm3, 6000, 1e-9);
  EXPECT_NEAR(f.PositiveVolumeMm3, 7 * 600, 1e-9);
  EXPECT_NEAR(f.NegativeVolumeMm3, 3 * 600, 1e-9);
  EXPECT_NEAR(f.CutAreaMm2, 600, 1e-9);
  const rp::CutFigures oblique = rp::CutBone(box, {5, 10, 15}, rp::Normalized({0, 1, 1}));
  EXPECT_NEAR(oblique.PositiveVolumeMm3, 3000, 1e-9);  // through the centre: halves
  EXPECT_NEAR(oblique.CutAreaMm2, 10 * 20 * std::sqrt(2.0), 1e-9);  // the plane crosses the 20 x 20 part diagonally
  const rp::CutFigures outside = rp::CutBone(box, {50, 0, 0}, {1, 0, 0});
  EXPECT_NEAR(outside.PositiveVolumeMm3, 0, 1e-9);
  EXPECT_NEAR(outside.CutAreaMm2, 0, 1e-9);

  const double R = 10, d = 4;  // a plane 4 mm from the centre: cap of height R - d
  const rp::TriangleMesh sphere = rp::shapes::Sphere({0, 0, 0}, R, 6);
  const rp::CutFigures cap = rp::CutBone(sphere, {0, 0, d}, {0, 0, 1});
  const double h = R - d;
  EXPECT_NEAR(cap.PositiveVolumeMm3, Pi * h * h * (3 * R - h) / 3, 0.002 * cap.PositiveVolumeMm3);
  EXPECT_NEAR(cap.CutAreaMm2, Pi * (R * R - d * d), 0.002 * cap.CutAreaMm2);
  EXPECT_NEAR(cap.VolumeMm3, 4 * Pi * R * R * R / 3, 0.002 * cap.VolumeMm3);
}

TEST(PlanningCore, TheScrewsSurfaceIsClosedAndHasTheScrewsVolume) {
  rp::TrajectorySnapshot screw = Trajectory({0, 0, 0}, {0, 0, 50}, 3.2);
  screw.IsScrew = true;
  screw.ScrewDiameterMm = 6, screw.ScrewLengthMm = 40, screw.HeadDiameterMm = 10, screw.HeadLengthMm = 5;
  const int n = 64;
  rp::TriangleMesh mesh = rp::MakeScrewMesh(screw, n);
  rp::MeshSignedDistance closed;
  std::string error;
  ASSERT_TRUE(closed.Build(mesh, error)) << error;  // closed and manifold
  const rp::CutFigures whole = rp::CutBone(mesh, {0, 0, 0}, {0, 0, 1});
  const double polygon = 0.5 * n * std::sin(2 * Pi / n) / Pi;  // a regular n-gon's area over its circle's
  const double r = 3;
  const double expected = polygon * Pi * (r * r * (40 - r) + r * r * r / 3 + 25 * 5);
  EXPECT_NEAR(whole.VolumeMm3, expected, 1e-9 * expected);  // positive: outward triangles
  EXPECT_LT(closed.SignedDistance({0, 0, 49.5}), 0);  // just behind the tip, inside
  EXPECT_GT(closed.SignedDistance({0, 0, 50.5}), 0);
  EXPECT_LT(closed.SignedDistance({0, 0, 7}), 0);     // the head: 5 mm behind the shaft's end at 10
  EXPECT_GT(closed.SignedDistance({0, 0, 4.5}), 0);
}

TEST(PlanningCore, TheProposalFindsTheAnalyticBestEntryWithinTheCandidateSpacing) {
  // Four spheres around the axis S at 15 mm, between a target at the origin and an entry plane at
  // S = 50: by symmetry the entry farthest from all four is on the axis, (0, 0, 50).
  const double R = 5, r = 1;
  std::vector<rp::StructureAtRiskSnapshot> structures;
  for (const rp::Vec3 c : {rp::Vec3{15, 0, 25}, rp::Vec3{-15, 0, 25}, rp::Vec3{0, 15, 25}, rp::Vec3{0, -15, 25}})
    structures.push_back(Structure("sphere", rp::shapes::Sphere(c, R, 4), 1.0));
  rp::ProposalRequest request;
  request.ToolDiameterMm = 2 * r;
  const double spacing = 0.7;
  for (double x = -20.3; x <= 20.3; x += spacing)
    for (double y = -20.1; y <= 20.1; y += spacing) request.Candidates.push_back({x, y, 50});
  request.Best = 3;
  const rp::ProposalResult result = rp::ProposeTrajectory(request, structures, nullptr);
  ASSERT_TRUE(result.Error.empty()) << result.Error;
  ASSERT_EQ(result.Best.size(), 3u);
  const rp::Vec3 best = request.Candidates[static_cast<size_t>(result.Best[0])];
  EXPECT_LE(rp::Norm(best - rp::Vec3{0, 0, 50}), spacing) << best.x << " " << best.y;
  EXPECT_NEAR(result.SpacingMm, spacing, 1e-9);
  // The axis misses each sphere by 15 - R (up to the icosphere's flats and the candidate's offset).
  const rp::CandidateScore& score = result.Scores[static_cast<size_t>(result.Best[0])];
  EXPECT_NEAR(score.ClearanceMm, 15 - R - r, 0.5);
  EXPECT_NEAR(score.SlackMm, score.ClearanceMm - 1.0, 1e-5);
  // The others are at least three spacings away, and not better.
  for (size_t k = 1; k < result.Best.size(); ++k) {
    EXPECT_GE(rp::Norm(request.Candidates[static_cast<size_t>(result.Best[k])] - best), 3 * spacing - 1e-9);
    EXPECT_LE(result.Scores[static_cast<size_t>(result.Best[k])].SlackMm, score.SlackMm);
  }
  // One thread gives the same scores as two.
  request.Threads = 1;
  const rp::ProposalResult single = rp::ProposeTrajectory(request, structures, nullptr);
  for (size_t i = 0; i < single.Scores.size(); ++i) EXPECT_EQ(single.Scores[i].ClearanceMm, result.Scores[i].ClearanceMm);
}

TEST(PlanningCore, TheProposalCanKeepTheToolInBone) {
  // Bone: the tube's wall; the target in the wall. A path may start out of bone (in the canal or
  // outside the tube) but once in bone must stay in it to the target: through the canal it may not.
  const AnalyticVolume ct({-14, -14, -12}, {14, 14, 12}, 0.5, TubeHU);
  rp::TissueModel tissue;
  ct.Into(tissue.CT);
  AddBoneRanges(tissue);
  tissue.Prepare();
  rp::ProposalRequest request;
  request.Target = {8, 0, 10};
  request.ToolDiameterMm = 1;
  request.StayInBone = true;
  const struct {
    rp::Vec3 entry;
    bool inBone;
  } cases[] = {{{8, 0, -10}, true},   // in the wall all the way
               {{0, 0, -10}, true},   // from the canal into the wall, then in it
               {{12, 0, -10}, true},  // from outside into the wall
               {{-8, 0, -10}, false},  // the far wall, then across the canal
               {{-12, 0, -10}, false}};
  for (const auto& c : cases) request.Candidates.push_back(c.entry);
  const rp::ProposalResult result = rp::ProposeTrajectory(request, {}, &tissue);
  ASSERT_TRUE(result.Error.empty()) << result.Error;
  for (size_t i = 0; i < request.Candidates.size(); ++i)
    EXPECT_EQ(result.Scores[i].InBone, cases[i].inBone) << request.Candidates[i].x;
  for (int i : result.Best) EXPECT_TRUE(result.Scores[static_cast<size_t>(i)].InBone);
  // Without a CT or segmentation, staying in bone cannot be asked.
  rp::TissueModel none;
  none.Prepare();
  EXPECT_FALSE(rp::ProposeTrajectory(request, {}, &none).Error.empty());
}
