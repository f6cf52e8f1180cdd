// Known answers for the drilling core (issue 15):
//  - a straight stroke of length L, radius r into a homogeneous block removes πr²L + 4/3·πr³
//    within 2 % at 0.2 mm (the error shrinks with the grid), nothing farther than r + one voxel;
//  - the force on a flat face at depth d is k·d along the face normal (1 %), axis-aligned and
//    oblique; a 1 mm cortical shell is not popped through at 0.5 m/s (burr off: never; burr on:
//    not faster than the feed rate allows, and the force never turns inwards);
//  - a protected voxel is never removed and the burr stops there;
//  - undo restores the last stroke exactly, reset the bone as built;
//  - a cut carved in shares over several ticks equals the cut at once; a sample is the trilinear
//    interpolation of the voxels around it, across block faces too;
//  - a sweep handed the densities Touching sampled at its start is the sweep that samples them;
//  - the distance to a protected surface is, every tick, the closest point's (brute force);
//  - 0 allocations in 3000 drilling ticks;
//  - the mesh kept up to date block by block equals a whole re-contour, also while the servo,
//    display and main threads run together (run this test under ThreadSanitizer too).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "rpAllocationCounter.h"
#include "rpBVH.h"
#include "rpBlockMesher.h"
#include "rpDrillAnalytic.h"
#include "rpDrillServo.h"
#include "rpServoLoop.h"
#include "rpSimulatedDevice.h"

using rp::Vec3;

namespace {

std::vector<rp::Material> Materials() {
  rp::MaterialTable table;
  std::string error;
  EXPECT_TRUE(rp::LoadMaterialTable(table, error)) << error;
  return rp::DrillableMaterials(table);
}

uint8_t Cortical(const std::vector<rp::Material>& m) { return rp::FindDrillMaterial(m, "bone"); }
uint8_t Trabecular(const std::vector<rp::Material>& m) { return rp::FindDrillMaterial(m, "trabecular bone"); }

std::vector<uint8_t> Densities(const rp::DrillVolume& v) {
  std::vector<uint8_t> out;
  for (size_t s = 0; s < v.AllocatedBlocks(); ++s) {
    const auto* d = v.BlockDensities(static_cast<int32_t>(s));
    for (int i = 0; i < rp::DrillVolume::BlockVoxels; ++i) out.push_back(d[i].load());
  }
  return out;
}

double SegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(rp::Dot(p - a, ab) / rp::Norm2(ab), 0.0, 1.0);
  return rp::Norm(p - (a + ab * t));
}

// A drilling rig ticked by hand (1 kHz simulated time): volume, simulated device, servo.
struct Rig {
  std::vector<rp::Material> Mat = Materials();
  rp::DrillVolume Volume;
  rp::SimulatedDevice Device;
  std::unique_ptr<rp::DrillServo> Servo;
  rp::TickInfo Tick;

  explicit Rig(const rp::AnalyticBone& bone, double spacing, rp::DrillServoOptions options = {}) {
    std::string error;
    EXPECT_TRUE(rp::BuildAnalyticBone(bone, spacing, this->Mat, this->Volume, error)) << error;
    options.RampSeconds = 0;
    this->Servo = std::make_unique<rp::DrillServo>(this->Device, this->Volume, options);
    this->Tick.Period = 1e-3;
  }
  void Path(const std::vector<double>& t, const std::vector<Vec3>& p) {
    auto path = std::make_shared<rp::WaypointTrajectory>();
    std::string error;
    ASSERT_TRUE(path->Set(t, p, error)) << error;
    this->Device.SetTrajectory(path);
  }
  rp::DrillState Step() {
    this->Tick.Time = this->Tick.Index * 1e-3;
    this->Servo->Tick(this->Tick);
    ++this->Tick.Index;
    rp::DrillState s;
    this->Servo->ReadState(s);
    return s;
  }
};

// Drills from → to (burr starts at `from`, cutting) until the proxy arrives or `seconds` pass.
rp::DrillState Stroke(Rig& rig, const Vec3& from, const Vec3& to, double radius, double speed, double seconds) {
  const double t0 = rig.Tick.Index * 1e-3;
  rig.Path({0.0, t0 + 1e-3, t0 + 1e-3 + rp::Norm(to - from) / speed}, {from, from, to});
  rp::DrillControl on{true, radius, 60000};
  rig.Servo->SetControl(on);
  rig.Servo->PlaceBurr(from, on);
  rp::DrillState s;
  const uint64_t end = rig.Tick.Index + static_cast<uint64_t>(seconds * 1000);
  while (rig.Tick.Index < end) {
    s = rig.Step();
    if (rp::Norm(s.Proxy - to) < 1e-3) break;
  }
  for (int i = 0; i < 5; ++i) s = rig.Step();
  rig.Servo->SetControl({false, radius, 60000});
  const rp::DrillState off = rig.Step();  // the stroke ends: the cut in progress is finished
  s.RemovedTotalMm3 = off.RemovedTotalMm3;
  return s;
}

struct StrokeResult {
  double Removed = 0, Expected = 0, FarthestChange = 0;
  bool Arrived = false;
};

StrokeResult StraightStroke(double spacing) {
  const double r = 2.0, L = 10.0;
  const Vec3 from{0.13, -0.07, 6.0}, to{0.13, -0.07, -4.0};  // off the voxel lattice on purpose
  Rig rig(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, 1), spacing);
  const std::vector<uint8_t> before = Densities(rig.Volume);
  const rp::DrillState s = Stroke(rig, from, to, r, 5.0, 20.0);
  StrokeResult result;
  result.Arrived = rp::Norm(s.Proxy - to) < 1e-2;
  result.Removed = s.RemovedTotalMm3;
  result.Expected = M_PI * r * r * L + 4.0 / 3.0 * M_PI * r * r * r;
  const std::vector<uint8_t> after = Densities(rig.Volume);
  for (size_t s2 = 0; s2 < rig.Volume.AllocatedBlocks(); ++s2) {
    const auto c = rig.Volume.BlockCoordinate(static_cast<int32_t>(s2));
    for (int v = 0; v < rp::DrillVolume::BlockVoxels; ++v) {
      const size_t index = s2 * rp::DrillVolume::BlockVoxels + size_t(v);
      if (before[index] == after[index]) continue;
      const Vec3 p = rig.Volume.Grid().Center(c[0] * 8 + (v & 7), c[1] * 8 + ((v >> 3) & 7), c[2] * 8 + (v >> 6));
      result.FarthestChange = std::max(result.FarthestChange, SegmentDistance(p, from, to));
    }
  }
  // The removed volume the servo counted is what the densities say.
  double units = 0;
  for (size_t i = 0; i < before.size(); ++i) units += double(before[i]) - after[i];
  EXPECT_NEAR(units / 255.0 * rig.Volume.VoxelVolume(), result.Removed, 1e-6);
  return result;
}

}  // namespace

TEST(DrillVolume, BlockVolumeAndSparseStorage) {
  const auto mat = Materials();
  ASSERT_EQ(mat.size(), 2u) << "bone and trabecular bone carry a hardness in materials.json";
  rp::DrillVolume volume;
  std::string error;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-5, -4, -3}, {5, 4, 3.3}, 1), 0.3, mat, volume, error)) << error;
  // Σρ·h³ of the two-voxel ramp is the box's volume plus (h²/3)·∫H dA: for a box, h²·π/12 per
  // mm of edge (the ramp is rounded around convex edges).
  const double h = 0.3;
  const double expected = 10 * 8 * 6.3 + h * h * M_PI / 12 * 4 * (10 + 8 + 6.3);
  EXPECT_NEAR(volume.OriginalVolumes()[0], expected, 0.0005 * expected);
  // Only blocks near the box are stored.
  const size_t all = size_t(volume.BlockDimensions()[0]) * volume.BlockDimensions()[1] * volume.BlockDimensions()[2];
  EXPECT_LE(volume.AllocatedBlocks(), all);
  EXPECT_GT(volume.AllocatedBlocks(), 0u);
  // A far-away box in a large grid: empty blocks are not stored.
  rp::DrillVolume sparse;
  rp::AnalyticBone two = rp::BlockBone({0, 0, 0}, {2, 2, 2}, 1);
  two.Hi = {40, 40, 40};  // bounds far larger than the bone
  ASSERT_TRUE(rp::BuildAnalyticBone(two, 0.3, mat, sparse, error)) << error;
  const size_t sparseAll = size_t(sparse.BlockDimensions()[0]) * sparse.BlockDimensions()[1] * sparse.BlockDimensions()[2];
  EXPECT_LT(sparse.AllocatedBlocks() * 50, sparseAll);
  EXPECT_NEAR(sparse.OriginalVolumes()[0], 8.0 + h * h * M_PI / 12 * 24, 0.01 * 8.0);
  // Bad input is named.
  rp::DrillGrid bad;
  bad.Spacing = 0;
  EXPECT_FALSE(sparse.Initialize(bad, mat, error));
  EXPECT_NE(error.find("voxel size"), std::string::npos) << error;
}

TEST(DrillVolume, SampleIsTheTrilinearInterpolationAcrossBlockFaces) {
  // The sample at any point (inside a block, across its faces and corners, at the grid's edge)
  // equals the trilinear interpolation of the voxels around it, read one by one; the material
  // is the densest voxel's.
  const auto mat = Materials();
  rp::DrillVolume volume;
  std::string error;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-3, -4, -2}, {4, 3, 5}, Cortical(mat), 1.0, Trabecular(mat)), 0.25, mat,
                                    volume, error))
      << error;
  const rp::DrillGrid& g = volume.Grid();
  uint64_t state = 12345;
  const auto uniform = [&state]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  int acrossBlocks = 0;
  for (int n = 0; n < 20000; ++n) {
    Vec3 ras;
    for (int a = 0; a < 3; ++a) ras[a] = g.Origin[a] - g.Spacing + uniform() * (g.Dimensions[a] + 1) * g.Spacing;
    if (n % 4 == 0) ras.x = g.Origin.x + (8 * (1 + n % 5) - 0.5) * g.Spacing;  // on a block face
    const Vec3 x = g.ToIndex(ras);
    const int i = int(std::floor(x.x)), j = int(std::floor(x.y)), k = int(std::floor(x.z));
    double expected = 0;
    uint8_t densest = 0, code = 0;
    for (int c = 0; c < 8; ++c) {
      const int di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
      const double weight = (di ? x.x - i : 1 - (x.x - i)) * (dj ? x.y - j : 1 - (x.y - j)) * (dk ? x.z - k : 1 - (x.z - k));
      const uint8_t d = volume.Density(i + di, j + dj, k + dk);
      expected += weight * d / 255.0;
      if (d > densest) densest = d, code = volume.MaterialCode(i + di, j + dj, k + dk);
    }
    const bool inGrid = x.x >= -1 && x.y >= -1 && x.z >= -1 && x.x < g.Dimensions[0] && x.y < g.Dimensions[1] &&
                        x.z < g.Dimensions[2];
    if (!inGrid) expected = 0, code = 0;
    acrossBlocks += ((i & 7) == 7 || (j & 7) == 7 || (k & 7) == 7) && expected > 0;
    uint8_t sampledCode = 0xff;
    ASSERT_NEAR(volume.Sample(ras, sampledCode), expected, 1e-12) << "at " << ras.x << "," << ras.y << "," << ras.z;
    ASSERT_NEAR(volume.Sample(ras), expected, 1e-12);
    if (expected > 0) {
      ASSERT_EQ(sampledCode, code);
    }
  }
  EXPECT_GT(acrossBlocks, 1000);
}

TEST(Drilling, ACutInSharesLeavesTheBoneOneCutLeaves) {
  // BeginCut(…, 4) + three ContinueCut() carve exactly what Cut() carves at once, and count the
  // same volume; the cut is pending in between, and a stroke's end finishes it.
  const auto mat = Materials();
  std::string error;
  rp::DrillVolume once, shared;
  for (rp::DrillVolume* v : {&once, &shared})
    ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-6, -6, -6}, {6, 6, 6}, Cortical(mat)), 0.2, mat, *v, error)) << error;
  rp::BoneCutter a(once), b(shared);
  const Vec3 c0{0.11, -0.23, 4.5}, dir = rp::Normalized(Vec3{0.2, 0.1, -1});
  const double advance = 0.07;
  a.BeginStroke(), b.BeginStroke();
  ASSERT_TRUE(a.Cut(c0, 2.5).Removed);
  ASSERT_TRUE(b.Cut(c0, 2.5).Removed);
  ASSERT_TRUE(a.Cut(c0 + dir * advance, 2.5, dir, advance).Removed);
  const std::vector<uint8_t> before = Densities(shared);
  b.BeginCut(c0 + dir * advance, 2.5, dir, advance, 4);
  EXPECT_TRUE(b.CutPending());
  EXPECT_NE(Densities(shared), Densities(once)) << "one share is not the whole cut";
  EXPECT_NE(Densities(shared), before) << "the first share carves";
  b.ContinueCut();
  b.ContinueCut();
  EXPECT_TRUE(b.CutPending());
  b.EndStroke();  // finishes the last share
  EXPECT_FALSE(b.CutPending());
  EXPECT_EQ(Densities(shared), Densities(once));
  EXPECT_DOUBLE_EQ(b.RemovedTotal(), a.RemovedTotal());
  // Undo restores the stroke, the shared cut included.
  ASSERT_TRUE(b.StartUndo());
  while (b.Restoring()) b.Step();
  rp::DrillVolume fresh;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-6, -6, -6}, {6, 6, 6}, Cortical(mat)), 0.2, mat, fresh, error)) << error;
  EXPECT_EQ(Densities(shared), Densities(fresh));
}

TEST(BlockMesher, ClosedSurfaceHasTheBoneVolume) {
  const auto mat = Materials();
  rp::DrillVolume volume;
  std::string error;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-5, -4, -3}, {5, 4, 3.3}, 1), 0.3, mat, volume, error)) << error;
  rp::BlockMesher mesher(volume);
  mesher.ContourAll();
  EXPECT_GT(mesher.TriangleCount(), 1000u);
  // Outward triangles, volume of the box within half a percent (edges are rounded by the ramp).
  EXPECT_NEAR(mesher.EnclosedVolume(), 10 * 8 * 6.3, 0.005 * 504);
}

// A frame with more dirty blocks than one thread takes (the parallel path that checks each block
// on its own, without a pass over the whole volume) gives each block the mesh a whole re-contour gives.
TEST(BlockMesher, ManyDirtyBlocksInOneFrameEqualAWholeRecontour) {
  Rig rig(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, 1), 0.2);
  rp::BlockMesher frames(rig.Volume);
  frames.ContourAll();
  Stroke(rig, {0.13, -0.07, 14}, {0.13, -0.07, 9.5}, 2.0, 20.0, 5.0);
  const size_t dirty = frames.UpdateDirty();
  ASSERT_GE(dirty, rp::BlockMesher::ParallelBlocks) << "the stroke dirties enough blocks to go parallel";
  ASSERT_LT(dirty * 8, frames.Blocks().size()) << "and few enough not to classify the whole volume";
  rp::BlockMesher whole(rig.Volume);
  whole.ContourAll();
  ASSERT_EQ(frames.Blocks().size(), whole.Blocks().size());
  size_t differing = 0;
  for (size_t b = 0; b < whole.Blocks().size(); ++b)
    differing += frames.Blocks()[b].Points != whole.Blocks()[b].Points ||
                 frames.Blocks()[b].Triangles != whole.Blocks()[b].Triangles ||
                 frames.Blocks()[b].Materials != whole.Blocks()[b].Materials;
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(whole.TriangleCount(), 0u);
  EXPECT_LT(whole.EnclosedVolume(), 16 * 16 * 24 - 10.0) << "the stroke's hole is in the surface";
}

TEST(Drilling, StraightStrokeRemovesTheCapsuleVolume) {
  const StrokeResult fine = StraightStroke(0.2);
  ASSERT_TRUE(fine.Arrived);
  const double error = std::fabs(fine.Removed - fine.Expected) / fine.Expected;
  EXPECT_LT(error, 0.02) << "removed " << fine.Removed << " mm³, expected " << fine.Expected;
  EXPECT_LE(fine.FarthestChange, 2.0 + 0.2 + 1e-9) << "removal beyond r + one voxel";
  // Coarser grids: still bounded by r + one voxel, and the error grows with the voxel.
  const StrokeResult coarse = StraightStroke(0.5);
  ASSERT_TRUE(coarse.Arrived);
  EXPECT_LE(coarse.FarthestChange, 2.0 + 0.5 + 1e-9);
  const double coarseError = std::fabs(coarse.Removed - coarse.Expected) / coarse.Expected;
  EXPECT_LT(error, coarseError);
}

namespace {
// Holds the burr (burr off) at depth d into a plane with outward normal n through the origin;
// returns the force and the rendered stiffness.
void FlatFace(const Vec3& n, double depth, double spacing, Vec3& force, double& k) {
  const double r = 2.0;
  rp::AnalyticBone plane;
  plane.Lo = {-12, -12, -12};
  plane.Hi = {12, 12, 12};
  plane.SignedDistance = [n](const Vec3& p) {
    return std::max(rp::Dot(p, n), rp::BoxSignedDistance(p, {-12, -12, -12}, {12, 12, 12}));
  };
  Rig rig(plane, spacing);
  Vec3 lateral{0.031, -0.017, 0.023};  // off the lattice, across the normal
  lateral -= n * rp::Dot(lateral, n);
  const Vec3 start = lateral + n * (r + 5), held = lateral + n * (r - depth);
  rig.Path({0.0, 0.3, 0.6}, {start, held, held});
  rig.Servo->SetControl({false, r, 60000});
  rp::DrillState s;
  for (int i = 0; i < 600; ++i) s = rig.Step();
  force = s.Force;
  k = s.Stiffness;
  EXPECT_TRUE(s.Contact);
}
}  // namespace

TEST(Drilling, FlatFaceForceIsStiffnessTimesDepth) {
  for (const Vec3& n : {Vec3{0, 0, 1}, rp::Normalized(Vec3{1, 1, 0}), rp::Normalized(Vec3{1, -2, 2})}) {
    for (double depth : {0.4, 0.8, 1.2}) {
      Vec3 f;
      double k = 0;
      FlatFace(n, depth, 0.2, f, k);
      ASSERT_GT(k, 0);
      const Vec3 expected = n * (k * depth);
      EXPECT_LT(rp::Norm(f - expected), 0.01 * k * depth)
          << "normal (" << n.x << "," << n.y << "," << n.z << ") depth " << depth << ": force (" << f.x << ","
          << f.y << "," << f.z << "), expected |F| " << k * depth;
    }
  }
}

TEST(Drilling, ThinCortexIsNotPoppedThroughAtHalfAMetrePerSecond) {
  const auto mat = Materials();
  // A 1 mm cortical plate, air on both sides; the burr comes down at 0.5 m/s to 10 mm below it.
  const rp::AnalyticBone plate = rp::BlockBone({-10, -10, -0.5}, {10, 10, 0.5}, Cortical(mat));
  const double r = 2.0;
  for (bool burr : {false, true}) {
    Rig rig(plate, 0.2);
    rig.Path({0.0, 0.03, 2.0}, {{0.1, 0.1, 5}, {0.1, 0.1, -10}, {0.1, 0.1, -10}});
    rig.Servo->SetControl({burr, r, 60000});
    double firstThrough = -1;
    for (int i = 0; i < 2000; ++i) {
      const rp::DrillState s = rig.Step();
      EXPECT_GE(s.Force.z, -1e-9) << "the force pulled the hand into the plate at t = " << s.Time;
      if (!burr) {
        EXPECT_GE(s.Proxy.z, 0.5 + r - 0.05) << "proxy inside the plate at t = " << s.Time;
      }
      if (firstThrough < 0 && s.Proxy.z < 0.5 + r - 1.0) firstThrough = s.Time;  // sphere's bottom past the plate
    }
    if (burr) {
      // Cutting 1 mm of hardness-1 bone at most at the feed rate (2 mm/s at the device's maximum force).
      ASSERT_GT(firstThrough, 0) << "the burr never cut through";
      EXPECT_GT(firstThrough, 0.03 + (1.0 - 0.3) / 2.0);
    }
  }
}

TEST(Drilling, ProtectedVoxelsAreNeverRemoved) {
  const auto mat = Materials();
  rp::AnalyticBone bone = rp::BlockBone({-8, -8, -12}, {8, 8, 12}, Cortical(mat));
  bone.Protected = [](const Vec3& p) { return p.z < -3.0; };  // e.g. the posterior cortex
  Rig rig(bone, 0.25);
  std::vector<uint8_t> protectedBefore;
  const auto before = Densities(rig.Volume);
  const rp::DrillState s = Stroke(rig, {0, 0, 6}, {0, 0, -8}, 2.0, 5.0, 12.0);
  const auto after = Densities(rig.Volume);
  EXPECT_GT(s.RefusedTicks, 0u);
  EXPECT_GT(s.RemovedTotalMm3, 50.0);  // it drilled down to the protected layer
  size_t protectedVoxels = 0;
  for (size_t b = 0; b < rig.Volume.AllocatedBlocks(); ++b) {
    const uint8_t* codes = rig.Volume.BlockMaterials(static_cast<int32_t>(b));
    for (int v = 0; v < rp::DrillVolume::BlockVoxels; ++v) {
      if (!(codes[v] & rp::DrillVolume::ProtectedBit)) continue;
      ++protectedVoxels;
      const size_t index = b * rp::DrillVolume::BlockVoxels + size_t(v);
      ASSERT_EQ(before[index], after[index]) << "a protected voxel was drilled";
    }
  }
  EXPECT_GT(protectedVoxels, 1000u);
  // The burr stopped above the layer: its sphere reaches at most one voxel into the ramp.
  EXPECT_GT(s.Proxy.z, -3.0 + 2.0 - 0.3);
}

TEST(Drilling, UndoRestoresTheLastStrokeAndResetTheBone) {
  const auto mat = Materials();
  Rig rig(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, Cortical(mat), 1.0, Trabecular(mat)), 0.3);
  const auto original = Densities(rig.Volume);
  const rp::DrillState a = Stroke(rig, {0, 0, 14}, {0, 0, 4}, 1.5, 5.0, 15.0);
  const auto afterA = Densities(rig.Volume);
  ASSERT_GT(a.RemovedTotalMm3, 10.0);
  // Through the 1 mm cortex into the trabecular core: both tissues are counted.
  const uint8_t cortical = Cortical(mat), trabecular = Trabecular(mat);
  EXPECT_GT(a.RemovedMm3[cortical - 1], 2.0);
  EXPECT_GT(a.RemovedMm3[trabecular - 1], 10.0);
  const rp::DrillState b = Stroke(rig, {3, 0, 14}, {3, 0, 2}, 1.5, 5.0, 15.0);
  ASSERT_GT(b.RemovedTotalMm3, a.RemovedTotalMm3 + 10.0);
  EXPECT_EQ(b.UndoableStrokes, 2);
  rig.Servo->RequestUndo();
  rp::DrillState s;
  for (int i = 0; i < 50; ++i) s = rig.Step();
  EXPECT_FALSE(s.Restoring);
  EXPECT_EQ(Densities(rig.Volume), afterA);
  EXPECT_NEAR(s.RemovedTotalMm3, a.RemovedTotalMm3, 1e-9);
  EXPECT_EQ(s.UndoableStrokes, 1);
  rig.Servo->RequestReset();
  for (int i = 0; i < 200; ++i) s = rig.Step();
  EXPECT_FALSE(s.Restoring);
  EXPECT_EQ(Densities(rig.Volume), original);
  EXPECT_EQ(s.RemovedTotalMm3, 0.0);
  EXPECT_EQ(s.UndoableStrokes, 0);
}

TEST(BurrProxy, ASweepGivenTouchingsDensitiesIsTheSweepThatSamplesThem) {
  // Update() hands each pass's sweep the densities the last Touching sampled where it starts:
  // the result must be the same to the bit, in free space, grazing, touching and in bone.
  const auto mat = Materials();
  rp::DrillVolume volume;
  std::string error;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-6, -6, -6}, {6, 6, 6}, Cortical(mat)), 0.3, mat, volume, error))
      << error;
  const double r = 2.0;
  int blocked = 0, free = 0;
  for (int i = 0; i < 400; ++i) {
    // Burr centres from 1 mm inside the top face to 2 mm above its surface, moves in all directions.
    const Vec3 from{-3.0 + 0.015 * i, 1.7 - 0.008 * i, 6.0 + r - 1.0 + 3.0 * ((i * 37) % 100) / 100.0};
    const double a = 0.7 * i, b = 0.3 * i;
    const Vec3 to = from + Vec3{std::cos(a) * std::sin(b), std::sin(a) * std::sin(b), std::cos(b)} * (0.05 + 0.01 * (i % 50));
    double shell[rp::BurrProxy::ShellPoints];
    rp::BurrContact contact;
    rp::BurrProxy::Touching(volume, from, r, to - from, contact, shell);
    double sampledOverlap = -1, givenOverlap = -1;
    const double sampled = rp::BurrProxy::Sweep(volume, from, to, r, sampledOverlap);
    const double given = rp::BurrProxy::Sweep(volume, from, to, r, givenOverlap, shell);
    EXPECT_EQ(sampled, given) << "move " << i;
    EXPECT_EQ(sampledOverlap, givenOverlap) << "move " << i;
    blocked += sampled <= 1.0;
    free += sampled > 1.0;
  }
  EXPECT_GT(blocked, 50);
  EXPECT_GT(free, 50);
}

TEST(Drilling, TheProtectedDistanceIsTheClosestPointsEveryTick) {
  // The servo starts each tick's search from the last closest point: the distance must still
  // be the exact one, here against every triangle of a sphere beside and below the stroke.
  const auto mat = Materials();
  Rig rig(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, Cortical(mat)), 0.3);
  const Vec3 centre{4.0, 1.0, 7.0};
  const rp::TriangleMesh sphere = rp::shapes::Sphere(centre, 1.5, 3);
  rp::BVH tree;
  tree.Build(sphere);
  rig.Servo->SetProtectedSurface(&tree);
  const double r = 1.5;
  rig.Path({0.0, 0.3, 1.3, 2.3, 3.3}, {{0, 0, 14}, {0, 0, 12}, {0, 0, 6}, {1.5, 1.0, 4}, {-2, 3, 9}});
  rig.Servo->SetControl({true, r, 60000});
  double worst = 0, nearest = HUGE_VAL;
  for (int i = 0; i < 3300; ++i) {
    const rp::DrillState s = rig.Step();
    double closest2 = HUGE_VAL;
    for (const auto& t : sphere.Triangles) {
      double bary[3];
      const Vec3 q = rp::BVH::ClosestPointOnTriangle(s.Proxy, sphere.Points[size_t(t[0])], sphere.Points[size_t(t[1])],
                                                     sphere.Points[size_t(t[2])], bary);
      closest2 = std::min(closest2, rp::Norm2(q - s.Proxy));
    }
    worst = std::max(worst, std::fabs(s.ProtectedDistance - (std::sqrt(closest2) - r)));
    nearest = std::min(nearest, s.ProtectedDistance);
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(nearest, 4.0) << "the burr came near the sphere";
  rp::DrillState s;
  rig.Servo->ReadState(s);
  EXPECT_NEAR(s.ClosestApproach, nearest, 1e-12);
}

TEST(Drilling, ThreeThousandTicksDoNotAllocate) {
  const auto mat = Materials();
  rp::AnalyticBone bone = rp::BlockBone({-8, -8, -12}, {8, 8, 12}, Cortical(mat), 1.0, Trabecular(mat));
  bone.Protected = [](const Vec3& p) { return p.z < -8.0; };
  Rig rig(bone, 0.3);
  rig.Servo->EnableRecords(true);
  rig.Path({0.0, 0.5, 1.5, 3.5}, {{0, 0, 14}, {0, 0, 10}, {1, 0, 0}, {1, 0, 6}});
  rig.Servo->SetControl({true, 2.0, 60000});
  for (int i = 0; i < 10; ++i) rig.Step();  // first tick, first contact
  const uint64_t before = rp::alloc::ThreadAllocations();
  int cutting = 0;
  for (int i = 0; i < 3000; ++i) {
    if (i == 1800) rig.Servo->SetControl({false, 2.0, 60000});
    if (i == 1900) rig.Servo->RequestUndo();
    if (i == 2500) rig.Servo->SetControl({true, 2.5, 80000});
    cutting += rig.Step().Cutting;
  }
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
  EXPECT_GT(cutting, 500) << "the hot path really cut bone";
  rp::DrillRecord r;
  int records = 0;
  while (rig.Servo->Records().TryPop(r)) ++records;
  EXPECT_GE(records, 3000);
}

TEST(Drilling, BlockByBlockMeshEqualsWholeRecontourAcrossThreads) {
  const auto mat = Materials();
  auto volume = std::make_unique<rp::DrillVolume>();
  std::string error;
  ASSERT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-8, -8, -10}, {8, 8, 10}, Cortical(mat), 1.0, Trabecular(mat)),
                                    0.3, mat, *volume, error))
      << error;
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  // Down into the bone, out again (an undo happens meanwhile), down elsewhere.
  ASSERT_TRUE(path->Set({0.0, 0.3, 0.7, 0.9, 1.4}, {{0, 0, 13}, {0, 0, 9}, {2, 1, 4}, {4, 2, 13}, {4, 2, 6}}, error))
      << error;
  device.SetTrajectory(path);
  rp::DrillServoOptions options;
  options.FeedRate = 20.0;  // cut fast: many blocks change while the display reads them
  rp::DrillServo servo(device, *volume, options);
  servo.SetControl({true, 2.0, 60000});
  rp::BlockMesher mesher(*volume);
  mesher.ContourAll();
  rp::ServoLoop loop;
  rp::ServoLoop::Options loopOptions;
  loopOptions.RequestRealTimePriority = false;
  ASSERT_TRUE(loop.Start(&servo, loopOptions, error)) << error;
  std::atomic<bool> stop{false};
  std::atomic<int> frames{0};
  std::thread display([&] {
    while (!stop.load()) {
      if (mesher.UpdateDirty() > 0) frames.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  // Main thread: read the state at display rate, switch the burr, undo once.
  rp::DrillState s;
  for (int i = 0; i < 60; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    servo.ReadState(s);
    if (i == 28) servo.SetControl({false, 2.0, 60000});
    if (i == 30) servo.RequestUndo();
    if (i == 34) servo.SetControl({true, 1.5, 60000});
  }
  loop.Stop();
  stop.store(true);
  display.join();
  mesher.UpdateDirty();
  EXPECT_GT(loop.Stats().Ticks, 1000u);
  EXPECT_GT(frames.load(), 5);
  servo.ReadState(s);
  EXPECT_GE(s.Strokes, 2u);
  EXPECT_GT(s.RemovedTotalMm3, 1.0);
  rp::BlockMesher whole(*volume);
  whole.ContourAll();
  EXPECT_EQ(mesher.TriangleCount(), whole.TriangleCount());
  EXPECT_NEAR(mesher.EnclosedVolume(), whole.EnclosedVolume(), 1e-6 * std::fabs(whole.EnclosedVolume()));
  // And the mesh's volume is the voxels' (the iso-surface of the ramp).
  const auto now = volume->CurrentVolumes();
  EXPECT_NEAR(whole.EnclosedVolume(), now[0] + now[1], 0.01 * (now[0] + now[1]));
}

namespace {
// A fixture that forbids every cut and holds the burr's centre above S = Top with a spring k (the
// simplest depth stop): what the guidance issue's fixtures plug into.
class StopAbove : public rp::ToolConstraint {
 public:
  StopAbove(double top, double k) : Top(top), K(k) {}
  void Evaluate(const rp::ConstraintContext& tool, rp::ConstraintForce& out) noexcept override {
    out.ForbidCut = true;
    const double depth = this->Top - tool.Tip.z;
    if (depth <= 0) return;
    out.Force += Vec3{0, 0, this->K * depth};
    out.Stiffness += this->K;
    out.StoredEnergy += 0.5 * this->K * depth * depth;
    out.Engaged = true;
  }
  double Top, K;
};
}  // namespace

TEST(DrillServo, AFixtureForbidsTheCutAndPushesBackInsideTheClamp) {
  // The burr pressed 1 mm into the block's top (S = 12) with the burr on: with the fixture nothing
  // is removed and the force is the bone's spring plus the fixture's, clamped; without it the
  // burr cuts its way down.
  auto press = [](bool fixture, rp::DrillState& s) {
    Rig rig(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, 1), 0.3);
    if (fixture) {
      auto set = std::make_unique<rp::ToolConstraints>();
      set->Add(std::make_unique<StopAbove>(14.0, 0.5));
      rig.Servo->Constraints().Publish(std::move(set));
    }
    rig.Path({0.0, 0.1}, {{0, 0, 16}, {0, 0, 13}});  // burr centre 1 mm above the face, radius 2
    rig.Servo->SetControl({true, 2.0, 60000});
    rig.Servo->ServoStarted();
    for (int i = 0; i < 5; ++i) s = rig.Step();  // the first contact
    const uint64_t before = rp::alloc::ThreadAllocations();
    for (int i = 0; i < 600; ++i) s = rig.Step();
    EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
  };
  rp::DrillState guided, free;
  press(true, guided);
  press(false, free);
  EXPECT_EQ(guided.RemovedTotalMm3, 0.0);
  EXPECT_FALSE(guided.Cutting);
  EXPECT_GT(free.RemovedTotalMm3, 0.1);
  // The fixture's 0.5 N/mm over 1 mm beside the bone's contact, the sum within the device's maximum.
  EXPECT_TRUE(guided.Contact);
  EXPECT_GT(guided.Force.z, 0.5);
  EXPECT_LE(rp::Norm(guided.Force), rp::SimulatedDevice::DefaultInfo().MaxForce + 1e-9);
}
