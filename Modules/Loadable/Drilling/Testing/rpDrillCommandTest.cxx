// `roboplan drill` end to end: the analytic block's stroke volume (known answer) through the
// loaded module, a recorded path replayed to the same removal, a labelmap with a protected
// segment (the burr stops there, nothing protected removed) and a CT giving cortical and
// trabecular bone, bad arguments (exit 2) and bad files (exit 1), the real knee CT's tibia
// when ../shared/data is present, a tracked drill driving the burr through the logic in RAS, and
// a plan drilled by the simulated hand with its fixtures and scored (`--plan`).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <sys/wait.h>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "rpBVH.h"
#include "rpDrillAnalytic.h"
#include "rpDrillBoneBuilder.h"
#include "rpDrillCommand.h"
#include "rpDrillSession.h"
#include "rpSharedData.h"
#include "rpSimulatedDevice.h"
#include "rpHapticSceneBridge.h"
#include "rpNodeStorage.h"
#include "rpVolumeIO.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrajectoryNode.h"

namespace fs = std::filesystem;

namespace {

fs::path TestDir(const std::string& name) {
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct DrillRun {
  int Code = -1;
  std::string Out, Err;
  nlohmann::json Json() const { return nlohmann::json::parse(this->Out); }
};

DrillRun Drill(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  DrillRun r;
  r.Code = rp::RunDrillCommand(args, nullptr, out, err);
  r.Out = out.str();
  r.Err = err.str();
  return r;
}

// A labelmap (1 mm, LPS-free RAS grid) with a bone box (label 1) and a protected slab under it
// (label 2), and a CT: 1300 HU within 1.5 mm of the bone's surface, 300 HU inside.
void WriteBoneFiles(const fs::path& labels, const fs::path& ct) {
  vtkNew<vtkImageData> l, c;
  const int n[3] = {40, 40, 50};
  l->SetDimensions(n[0], n[1], n[2]);
  l->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  c->SetDimensions(n[0], n[1], n[2]);
  c->AllocateScalars(VTK_SHORT, 1);
  vtkNew<vtkMatrix4x4> ijkToRAS;  // voxel (i,j,k) at RAS (i−20, j−20, k−25) mm
  ijkToRAS->SetElement(0, 3, -20);
  ijkToRAS->SetElement(1, 3, -20);
  ijkToRAS->SetElement(2, 3, -25);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const double x = i - 20, y = j - 20, z = k - 25;
        const bool bone = std::fabs(x) <= 12 && std::fabs(y) <= 12 && z >= -8 && z <= 12;
        const bool guarded = std::fabs(x) <= 12 && std::fabs(y) <= 12 && z >= -14 && z < -8;
        const double inside = std::min({12 - std::fabs(x), 12 - std::fabs(y), z + 8, 12 - z});
        static_cast<unsigned char*>(l->GetScalarPointer(i, j, k))[0] = bone ? 1 : (guarded ? 2 : 0);
        static_cast<short*>(c->GetScalarPointer(i, j, k))[0] = bone ? (inside < 1.5 ? 1300 : 300) : (guarded ? 60 : 0);
      }
  std::string error;
  ASSERT_TRUE(rp::WriteVolumeFile(labels.string(), l, ijkToRAS, {}, error)) << error;
  ASSERT_TRUE(rp::WriteVolumeFile(ct.string(), c, ijkToRAS, {}, error)) << error;
}

}  // namespace

TEST(DrillCommand, BlockStrokeRemovesTheCapsuleThroughTheModule) {
  const fs::path dir = TestDir("block");
  const std::string command = std::string(ROBOPLAN_BINARY_DIR) +
                              "/bin/roboplan drill --block --block-bounds -10,-10,-12,10,10,12 --burr-radius 2 "
                              "--from 0.13,-0.07,6 --to 0.13,-0.07,-4 --speed 5 --voxel 0.25 --json 2> " +
                              (dir / "stderr.txt").string();
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
  const auto doc = nlohmann::json::parse(output);
  const double expected = M_PI * 4 * 10 + 4.0 / 3.0 * M_PI * 8;
  EXPECT_NEAR(doc["expectedVolumeMm3"].get<double>(), expected, 1e-9);
  EXPECT_NEAR(doc["removedVolumeMm3"].get<double>(), expected, 0.02 * expected);
  EXPECT_TRUE(doc["stroke"]["reachedTarget"].get<bool>());
  EXPECT_LE(doc["farthestRemovalFromPathMm"].get<double>(), 2.0 + 0.25 + 1e-9);
  for (const char* key : {"servoTickP99Us", "dirtyBlockRecontourP95Ms", "peakForceN", "wholeBoneRecontourMs"})
    EXPECT_TRUE(doc.contains(key)) << key;
  EXPECT_GT(doc["servoTickP99Us"].get<double>(), 0);
  EXPECT_GT(doc["displayFrames"].get<size_t>(), 10u);
  EXPECT_GT(doc["peakForceN"].get<double>(), 0.5);
  EXPECT_LE(doc["peakForceN"].get<double>(), 3.3 + 1e-9);  // eq. 6: the device's maximum
}

TEST(DrillCommand, ARecordedPathReplaysToTheSameRemoval) {
  const fs::path dir = TestDir("replay");
  const std::string record = (dir / "path.txt").string();
  const DrillRun first = Drill({"--block", "--shell", "1", "--block-bounds", "-10,-10,-10,10,10,10", "--burr-radius", "1.5",
                           "--from", "3,0,14", "--to", "2,1,3", "--speed", "8", "--voxel", "0.4", "--record", record,
                           "--json"});
  ASSERT_EQ(first.Code, 0) << first.Err;
  const auto a = first.Json();
  EXPECT_GT(a["removedByTissueMm3"]["bone"].get<double>(), 2.0);
  EXPECT_GT(a["removedByTissueMm3"]["trabecular bone"].get<double>(), 5.0);
  const DrillRun second = Drill({"--block", "--shell", "1", "--block-bounds", "-10,-10,-10,10,10,10", "--replay", record, "--json"});
  ASSERT_EQ(second.Code, 0) << second.Err;
  const auto b = second.Json();
  // The same removal up to the recording's 1 µm rounding of the positions.
  EXPECT_NEAR(b["removedVolumeMm3"].get<double>(), a["removedVolumeMm3"].get<double>(),
              1e-4 * a["removedVolumeMm3"].get<double>());
  EXPECT_EQ(b["stroke"]["stopReason"], "replayed");
  // A broken recording is named.
  std::ofstream(dir / "broken.txt") << "# RoboPlan drill recording 1\n0.0 1 2 3\n";
  const DrillRun broken = Drill({"--block", "--replay", (dir / "broken.txt").string()});
  EXPECT_EQ(broken.Code, 1);
  EXPECT_NE(broken.Err.find("broken.txt:2"), std::string::npos) << broken.Err;
}

TEST(DrillCommand, RealTimeStrokeOnTheServoAndDisplayThreads) {
  // The 1 kHz servo thread, the 30 Hz display thread and the caller, on the wall clock.
  const DrillRun run = Drill({"--block", "--shell", "0.5", "--block-bounds", "-8,-8,-8,8,8,8", "--burr-radius", "1.5",
                              "--from", "0,0,10", "--to", "0,0,4", "--speed", "10", "--voxel", "0.4", "--realtime",
                              "--json"});
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = run.Json();
  EXPECT_TRUE(doc["stroke"]["realtime"].get<bool>());
  EXPECT_TRUE(doc["stroke"]["reachedTarget"].get<bool>()) << doc.dump(2);
  EXPECT_GT(doc["ticks"].get<int>(), 300);
  EXPECT_GT(doc["displayFrames"].get<int>(), 3);
  EXPECT_GT(doc["removedVolumeMm3"].get<double>(), 10.0);
  EXPECT_TRUE(doc["servo"].contains("periodP99Us"));
}

// A scripted stroke into a block, with a bone mesh every display frame or only the last one.
struct ScriptedStroke {
  std::vector<vtkSmartPointer<vtkPolyData>> Meshes;
  rp::DrillRunResult Result;
};
ScriptedStroke DrillScripted(bool meshEveryFrame) {
  rp::MaterialTable table;
  std::string error;
  EXPECT_TRUE(rp::LoadMaterialTable(table, error)) << error;
  const std::vector<rp::Material> materials = rp::DrillableMaterials(table);
  rp::DrillVolume volume;
  EXPECT_TRUE(rp::BuildAnalyticBone(rp::BlockBone({-6, -6, -6}, {6, 6, 6}, rp::FindDrillMaterial(materials, "bone")), 0.4,
                                    materials, volume, error))
      << error;
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  EXPECT_TRUE(path->Set({0.0, 2.0}, {{0, 0, 9}, {0, 0, 3}}, error)) << error;
  device.SetTrajectory(path);
  rp::DrillDisplay display(volume);
  display.Initialize();
  rp::DrillSession session(device, volume, display);
  rp::DrillSession::Options options;
  options.KeepPath = false;
  EXPECT_TRUE(session.Prepare(options, {}, nullptr, error)) << error;
  rp::DrillRunOptions run;
  run.Schedule = [](double) { return rp::DrillControl{true, 1.5, 60000}; };
  run.MaxSeconds = 2.0;
  run.MeshEveryFrame = meshEveryFrame;
  ScriptedStroke stroke;
  run.OnMesh = [&stroke](vtkPolyData* m) { stroke.Meshes.emplace_back(m); };
  EXPECT_TRUE(session.Run(run, stroke.Result, error)) << error;
  return stroke;
}

TEST(DrillRun, AScriptedRunAskedForTheLastMeshOnlyBuildsThatMeshAlone) {
  // The CLI and the demo keep only the last mesh: assembling the whole bone's mesh every frame on
  // the servo's thread evicted the servo's data from the cache every 33rd tick. Without those
  // assemblies the frames still re-contour, and the one mesh is the every-frame run's last.
  const ScriptedStroke every = DrillScripted(true), last = DrillScripted(false);
  ASSERT_GT(every.Meshes.size(), 3u);
  ASSERT_EQ(last.Meshes.size(), 1u);
  EXPECT_EQ(last.Result.Final.RemovedTotalMm3, every.Result.Final.RemovedTotalMm3);
  EXPECT_GT(last.Result.Final.RemovedTotalMm3, 2.0);
  size_t contoured = 0, assembled = 0;
  for (const rp::DisplayFrame& f : last.Result.Frames) {
    contoured += f.Blocks > 0 && f.AssembleMs == 0;
    assembled += f.Blocks == 0 && f.AssembleMs > 0;
  }
  EXPECT_EQ(assembled, 1u) << "the last mesh only";
  EXPECT_EQ(contoured + assembled, last.Result.Frames.size());
  EXPECT_EQ(contoured, every.Result.Frames.size()) << "the same frames re-contoured the same blocks";
  vtkPolyData* a = every.Meshes.back();
  vtkPolyData* b = last.Meshes.back();
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfPolys(), b->GetNumberOfPolys());
  double worst = 0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i) {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(p[c] - q[c]));
  }
  EXPECT_EQ(worst, 0.0);
}

TEST(DrillCommand, LabelmapWithProtectedSegmentAndCT) {
  const fs::path dir = TestDir("labels");
  WriteBoneFiles(dir / "labels.nrrd", dir / "ct.nrrd");
  // Down through the bone towards the protected slab under it.
  const DrillRun run = Drill({(dir / "labels.nrrd").string(), "--segment", "1", "--protect", "2", "--ct",
                         (dir / "ct.nrrd").string(), "--burr-radius", "2", "--from", "0,0,16", "--to", "0,0,-12",
                         "--speed", "10", "--voxel", "0.4", "--json"});
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = run.Json();
  EXPECT_EQ(doc["stroke"]["stopReason"], "protected");
  EXPECT_TRUE(doc["protected"]["stopped"].get<bool>());
  EXPECT_GT(doc["protected"]["refusedTicks"].get<int>(), 0);
  // The burr stopped where its sphere met the slab (top at z = −8.5 in the labels' ½ surface).
  EXPECT_LT(doc["protected"]["closestApproachMm"].get<double>(), 0.6);
  EXPECT_TRUE(doc["bone"]["materialsFromCT"].get<bool>());
  EXPECT_GT(doc["removedByTissueMm3"]["bone"].get<double>(), 5.0);
  EXPECT_GT(doc["removedByTissueMm3"]["trabecular bone"].get<double>(), 50.0);
  EXPECT_FALSE(doc.contains("expectedVolumeMm3"));
  // Unknown segment, missing --segment, bad numbers.
  const DrillRun unknown = Drill({(dir / "labels.nrrd").string(), "--segment", "7", "--burr-radius", "2", "--from", "0,0,16",
                             "--to", "0,0,0", "--speed", "10"});
  EXPECT_EQ(unknown.Code, 1);
  EXPECT_NE(unknown.Err.find("no segment '7'"), std::string::npos) << unknown.Err;
  const DrillRun missing = Drill({(dir / "labels.nrrd").string(), "--burr-radius", "2", "--from", "0,0,16", "--to", "0,0,0",
                             "--speed", "10"});
  EXPECT_EQ(missing.Code, 2);
  EXPECT_NE(missing.Err.find("--segment"), std::string::npos) << missing.Err;
  const DrillRun voxel = Drill({"--block", "--burr-radius", "2", "--from", "0,0,16", "--to", "0,0,0", "--speed", "10",
                           "--voxel", "0"});
  EXPECT_EQ(voxel.Code, 2);
  EXPECT_NE(voxel.Err.find("--voxel"), std::string::npos) << voxel.Err;
  const DrillRun both = Drill({(dir / "labels.nrrd").string(), "--block", "--burr-radius", "2", "--from", "0,0,16", "--to",
                          "0,0,0", "--speed", "10"});
  EXPECT_EQ(both.Code, 2);
  const DrillRun noFile = Drill({(dir / "nothing.nrrd").string(), "--segment", "1", "--burr-radius", "2", "--from",
                            "0,0,16", "--to", "0,0,0", "--speed", "10"});
  EXPECT_EQ(noFile.Code, 1);
  EXPECT_NE(noFile.Err.find("nothing.nrrd"), std::string::npos) << noFile.Err;
}

TEST(DrillCommand, RealKneeCTTibia) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/labels.nrrd");
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  const fs::path data = rptest::SharedDataPath("knee-ct-vhf");
  // The tibia (label 1): a tunnel from its anterior surface into its centre, fibula protected.
  vtkNew<vtkImageData> labels;
  vtkNew<vtkMatrix4x4> ijkToRAS;
  rp::VolumeFileData file;
  file.Image = labels;
  file.IJKToRAS = ijkToRAS;
  std::string error;
  ASSERT_TRUE(rp::ReadVolumeFile((data / "labels.nrrd").string(), file, error)) << error;
  double sum[3] = {0, 0, 0}, front = -1e9;
  long count = 0;
  int dims[3];
  labels->GetDimensions(dims);
  // The centroid of the tibia's upper third, and its most anterior point at that height.
  int kTop = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        if (labels->GetScalarComponentAsDouble(i, j, k, 0) == 1) kTop = std::max(kTop, k);
  const int kCentre = kTop - 60;  // the shaft: a thick cortex (near the plateau it is a thin shell, 250-400 HU at 1 mm)
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i)
      if (labels->GetScalarComponentAsDouble(i, j, kCentre, 0) == 1) {
        const double ijk[4] = {double(i), double(j), double(kCentre), 1}, *ras = ijkToRAS->MultiplyDoublePoint(ijk);
        sum[0] += ras[0], sum[1] += ras[1], sum[2] += ras[2], ++count;
        front = std::max(front, ras[1]);
      }
  ASSERT_GT(count, 100);
  const double c[3] = {sum[0] / count, sum[1] / count, sum[2] / count};
  char from[128], to[128];
  std::snprintf(from, sizeof from, "%.2f,%.2f,%.2f", c[0], front + 3.0, c[2]);
  std::snprintf(to, sizeof to, "%.2f,%.2f,%.2f", c[0], c[1], c[2]);
  const DrillRun run = Drill({(data / "labels.nrrd").string(), "--segment", "1", "--protect", "2", "--ct",
                         (data / "dicom").string(), "--burr-radius", "2.5", "--from", from, "--to", to, "--speed", "10",
                         "--voxel", "0.3", "--margin", "8", "--json"});
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = run.Json();
  EXPECT_TRUE(doc["bone"]["materialsFromCT"].get<bool>());
  EXPECT_TRUE(doc["stroke"]["reachedTarget"].get<bool>()) << doc.dump(2);
  // Through the real cortex into the cancellous bone.
  EXPECT_GT(doc["removedByTissueMm3"]["bone"].get<double>(), 10.0) << doc.dump(2);
  EXPECT_GT(doc["removedByTissueMm3"]["trabecular bone"].get<double>(), 10.0) << doc.dump(2);
  EXPECT_GT(doc["protected"]["closestApproachMm"].get<double>(), 0.0);
}

namespace {
// A sphere of radius 10 mm labelled in a 0.8 × 0.8 × 1.25 mm labelmap (the demo's CT grid) →
// the drill volume (0.3 mm) whose density follows `given` (empty: the labels meshed here) or,
// with `smooth` off, the label mask; a finite `top` limits the region to S <= top.
void BuildSphereBone(bool smooth, const rp::TriangleMesh& given, double top, rp::DrillVolume& bone,
                     rp::DrillBoneReport& report) {
  rp::DrillBoneSource source;
  source.Labels.Image = vtkSmartPointer<vtkImageData>::New();
  const double spacing[3] = {0.8, 0.8, 1.25};
  const int n[3] = {36, 36, 24};
  source.Labels.Image->SetDimensions(n[0], n[1], n[2]);
  source.Labels.Image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* labels = static_cast<unsigned char*>(source.Labels.Image->GetScalarPointer());
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const double x = (i - 17.3) * spacing[0], y = (j - 17.6) * spacing[1], z = (k - 11.2) * spacing[2];
        *labels++ = x * x + y * y + z * z <= 100.0 ? 1 : 0;
      }
  for (int a = 0; a < 3; ++a) source.Labels.IJKToRAS->SetElement(a, a, spacing[a]);
  source.Labels.IJKToRAS->SetElement(0, 3, -17.3 * spacing[0]);
  source.Labels.IJKToRAS->SetElement(1, 3, -17.6 * spacing[1]);
  source.Labels.IJKToRAS->SetElement(2, 3, -11.2 * spacing[2]);
  source.BoneLabels = {1};
  source.BoneTissues = {"bone"};
  source.Spacing = 0.3;
  source.SmoothSurface = smooth;
  source.BoneSurface = given;
  if (std::isfinite(top)) {
    source.HasRegion = true;
    source.RegionLo = {-30, -30, -30};
    source.RegionHi = {30, 30, top};
  }
  rp::MaterialTable table;
  std::string error;
  EXPECT_TRUE(rp::LoadMaterialTable(table, error)) << error;
  EXPECT_TRUE(rp::BuildDrillBone(source, rp::DrillableMaterials(table), bone, nullptr, report, error)) << error;
}

// The drill volume's ½ iso-surface (before drilling) against a surface: mean and 95 % of the
// distances from its vertices, and what the density followed.
struct SphereFit {
  double Mean = 0, P95 = 0;
  std::string Source;
};
SphereFit DrillSphere(bool smooth, const rp::TriangleMesh& given, const rp::TriangleMesh& against) {
  rp::DrillVolume bone;
  rp::DrillBoneReport report;
  BuildSphereBone(smooth, given, HUGE_VAL, bone, report);
  const rp::SurfaceFit fit = rp::MeasureSurfaceFit(bone, against);
  EXPECT_GT(fit.Vertices, 1000u);
  return {fit.MeanMm, fit.P95Mm, report.Surface};
}
}  // namespace

TEST(DrillBone, DensityFollowsTheBoneMeshNotTheLabelmapStaircase) {
  // The bone model the user sees (here: an icosphere of the labelled sphere) → the drill voxels
  // (0.3 mm): their iso-surface lies on it within a fraction of a voxel.
  const rp::TriangleMesh model = rp::shapes::Sphere({0, 0, 0}, 10.0, 4);
  const SphereFit fromModel = DrillSphere(true, model, model);
  EXPECT_EQ(fromModel.Source, "given mesh");
  EXPECT_LT(fromModel.Mean, 0.05 * 0.3) << "mean distance to the bone mesh (mm)";
  EXPECT_LT(fromModel.P95, 0.15 * 0.3) << "95 % distance to the bone mesh (mm)";
  // The trilinear label mask keeps the 0.8 × 0.8 × 1.25 mm staircase: far off the same sphere.
  const SphereFit fromMask = DrillSphere(false, {}, model);
  EXPECT_GT(fromMask.P95, 4 * fromModel.P95) << "the label mask's staircase";
  // No model given: the labels meshed here as the segment models are (Gaussian, volume-corrected)
  // follow the sphere far closer than the mask does.
  const SphereFit fromLabels = DrillSphere(true, {}, model);
  EXPECT_NE(fromLabels.Source.find("labels meshed"), std::string::npos) << fromLabels.Source;
  EXPECT_LT(fromLabels.P95, fromMask.P95) << "labels meshed " << fromLabels.P95 << " mm, mask " << fromMask.P95 << " mm";
  std::printf("iso-surface to the sphere: given mesh mean %.4f / p95 %.4f mm; labels meshed %.4f / %.4f; label mask %.4f / %.4f\n",
              fromModel.Mean, fromModel.P95, fromLabels.Mean, fromLabels.P95, fromMask.Mean, fromMask.P95);
}

TEST(DrillBone, ARegionOfTheBoneIsTheGivenModelCutByTheRegionNotTheLabels) {
  // The demo's case: the whole bone model given, the drill grid limited to a region that cuts the
  // bone. The model (radius 9 mm) lies a millimetre inside the labels (radius 10 mm), so only a
  // density built from the model passes: its iso-surface lies on the model within a fraction of a
  // voxel, and its volume is the ball's below the grid's top face, πc²(3R − c)/3 with c = R + top.
  const double R = 9.0, h = 0.3;
  const rp::TriangleMesh model = rp::shapes::Sphere({0, 0, 0}, R, 5);
  rp::DrillVolume bone;
  rp::DrillBoneReport report;
  BuildSphereBone(true, model, 3.0, bone, report);
  EXPECT_EQ(report.Surface, "given mesh");
  EXPECT_EQ(report.SurfaceTriangles, model.Triangles.size());
  const rp::DrillGrid& grid = bone.Grid();
  const double top = grid.Origin.z + (grid.Dimensions[2] - 0.5) * h;
  ASSERT_GT(top, 3.0);
  ASSERT_LT(top, R);
  const double c = R + top, expected = M_PI * c * c * (3 * R - c) / 3;
  double built = 0;
  for (double v : bone.OriginalVolumes()) built += v;
  EXPECT_NEAR(built, expected, 0.01 * expected) << "bone volume (mm³) below S = " << top;
  const rp::SurfaceFit onModel = rp::MeasureSurfaceFit(bone, model);
  EXPECT_GT(onModel.Vertices, 1000u);
  EXPECT_LT(onModel.MeanMm, 0.05 * h) << "mean distance to the model (mm)";
  EXPECT_LT(onModel.P95Mm, 0.15 * h) << "95 % distance to the model (mm)";
  const rp::SurfaceFit onLabels = rp::MeasureSurfaceFit(bone, rp::shapes::Sphere({0, 0, 0}, 10.0, 5));
  EXPECT_GT(onLabels.MeanMm, 0.9) << "the labels' surface is a millimetre out";
  std::printf("region cut at S = %.2f: volume %.1f mm³ (ball below it %.1f); to the model mean %.4f / p95 %.4f mm\n", top,
              built, expected, onModel.MeanMm, onModel.P95Mm);
}

TEST(DrillingLogic, ATrackedDrillDrivesTheBurrInRAS) {
  // A drill's tip tracked under TrackerToRAS drives the burr as it is (no trip through the scene's
  // rotated and scaled HapticDeviceToRAS and back): the burr's centre is the tip's RAS position.
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(scene);
  std::string error;
  ASSERT_TRUE(logic->BuildBlockBone({-10, -10, -10}, {10, 10, 10}, 0, 0.4, error)) << error;
  vtkNew<vtkRPLinearTransformNode> device;
  device->SetName(rp::HapticDeviceToRASName);
  const double scaled[16] = {2, 0, 0, 0, 0, 0, -2, 0, 0, 2, 0, 100, 0, 0, 0, 1};
  device->SetMatrixTransformToParent(scaled);
  scene->AddNode(device);
  vtkNew<vtkRPLinearTransformNode> tracker;
  const double rz90[16] = {0, -1, 0, 5, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // tracker (x, y, z) → RAS (5 − y, x, z)
  tracker->SetMatrixTransformToParent(rz90);
  scene->AddNode(tracker);
  vtkNew<vtkRPTrackedToolNode> tip;
  scene->AddNode(tip);
  ASSERT_TRUE(tip->SetAndObserveTransformNodeID(tracker->GetID()));
  auto place = [&](double z) {  // the tip at tracker (0, −3, z): RAS (8, 0, z)
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, -3, 0, 0, 1, z, 0, 0, 0, 1};
    tip->SetMatrixTransformToParent(m);
  };
  place(14);
  logic->SetBurrRadius(1.5);
  logic->SetFollowedNodeID(tip->GetID());
  ASSERT_TRUE(logic->StartSimulated(error)) << error;
  auto follow = [&](int frames) {
    for (int i = 0; i < frames; ++i) {
      logic->Update();
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
    }
  };
  follow(3);
  place(11);  // the burr 0.5 mm into the block's top (S = 10)
  follow(12);
  rp::DrillState s;
  ASSERT_TRUE(logic->ReadState(s));
  EXPECT_EQ(s.Hip.x, 8.0);
  EXPECT_EQ(s.Hip.y, 0.0);
  EXPECT_EQ(s.Hip.z, 11.0);
  EXPECT_TRUE(s.Contact);
  EXPECT_FALSE(s.Cutting);  // the burr is off
  EXPECT_GT(s.Force.z, 0.1);  // along +S in RAS (rotated by HapticDeviceToRAS it would be along A)
  EXPECT_LT(std::hypot(s.Force.x, s.Force.y), 0.01 * s.Force.z);
  logic->Stop();
  EXPECT_FALSE(logic->IsRunning());
}

namespace {
// Forbids every cut (a forbidden region everywhere).
struct ForbidEverything : rp::ToolConstraint {
  void Evaluate(const rp::ConstraintContext&, rp::ConstraintForce& out) noexcept override { out.ForbidCut = true; }
};
}  // namespace

TEST(DrillingLogic, EverySessionItRunsGetsTheFixtures) {
  // The same stroke with and without a fixture that forbids every cut, through RunSimulated.
  auto stroke = [](bool fixtures) {
    vtkNew<vtkRPScene> scene;
    vtkNew<vtkRPDrillingLogic> logic;
    logic->SetScene(scene);
    std::string error;
    EXPECT_TRUE(logic->BuildBlockBone({-6, -6, -6}, {6, 6, 6}, 0, 0.4, error)) << error;
    if (fixtures)
      logic->SetConstraints([] {
        auto set = std::make_unique<rp::ToolConstraints>();
        set->Add(std::make_unique<ForbidEverything>());
        return set;
      });
    logic->SetSimulatedTrajectory(rp::WaypointTrajectory::Line({0, 0, 9}, {0, 0, 3}, 3.0));
    rp::DrillRunOptions run;
    run.Schedule = [](double) { return rp::DrillControl{true, 1.5, 60000}; };
    run.MaxSeconds = 2.0;
    rp::DrillRunResult result;
    EXPECT_TRUE(logic->RunSimulated(run, result, error)) << error;
    return result.Final.RemovedTotalMm3;
  };
  EXPECT_GT(stroke(false), 1.0);
  EXPECT_EQ(stroke(true), 0.0);
}

// `roboplan drill --plan` (issue 38): the plan's trajectory drilled by the simulated hand (0.2 mm
// tremor, 1 mm/s drift) with its fixtures, scored. Down the plan into the bone with axis guidance
// and the depth stop: on the plan (0.5 mm, 1°), no deeper than the target by 0.1 mm. A plan whose
// target lies in the protected slab (a structure at risk, margin 1 mm) drilled with the forbidden
// region: the burr's surface never comes within the margin, and the depth stop is never reached.
TEST(DrillCommand, APlanDrilledWithItsFixturesIsScoredAgainstIt) {
  const fs::path dir = TestDir("plan");
  WriteBoneFiles(dir / "labels.nrrd", dir / "ct.nrrd");
  auto writePlan = [&](const std::string& name, double targetS) {
    vtkNew<vtkRPTrajectoryNode> trajectory;
    const double entry[3] = {0, 0, 12}, target[3] = {0, 0, targetS};
    trajectory->SetEntryAndTarget(entry, target);
    trajectory->SetToolDiameterMm(3);
    trajectory->SetName(name);
    const std::string path = (dir / (name + ".mrk.json")).string();
    std::string error;
    const rp::NodeStorage* storage = rp::FindNodeStorageForFile(path);
    EXPECT_TRUE(storage && storage->Write(trajectory, path, error)) << error;
    return path;
  };
  // A hand at 5 mm/s, faster than the default feed (2 mm/s at full force): the run waits for the burr.
  const std::vector<std::string> hand = {"--tremor", "0.2", "--drift", "1", "--seed", "3", "--voxel", "0.4", "--speed", "5",
                                         "--json"};
  auto drill = [&](const std::string& plan, const std::string& fixtures) {
    std::vector<std::string> args = {(dir / "labels.nrrd").string(), "--segment", "1", "--protect", "2:1", "--plan", plan,
                                     "--fixtures", fixtures};
    args.insert(args.end(), hand.begin(), hand.end());
    return Drill(args);
  };
  const DrillRun guided = drill(writePlan("tunnel", 0), "axis,depth");
  ASSERT_EQ(guided.Code, 0) << guided.Err;
  auto doc = guided.Json();
  for (const char* key : {"entryOffsetMm", "tipOffsetMm", "angleDeg", "depthErrorMm", "maxDeviationMm", "servoTickP99Us"})
    ASSERT_TRUE(doc.contains(key)) << key;
  EXPECT_LT(doc["entryOffsetMm"].get<double>(), 0.5);
  EXPECT_LT(doc["tipOffsetMm"].get<double>(), 0.5);
  // A 12 mm tunnel at 0.4 mm voxels: entry and tip within 0.5 mm bound the angle by atan(1/12) =
  // 4.8°; 1.6° measured (d02226d + main). The 1° is checked on rpGuidedDrillTest's 25 mm tunnel.
  EXPECT_LT(doc["angleDeg"].get<double>(), 2.0);
  EXPECT_LE(doc["depthErrorMm"].get<double>(), 0.1);
  EXPECT_GT(doc["depthErrorMm"].get<double>(), -0.5);
  EXPECT_FALSE(doc["enteredForbidden"].get<bool>());
  EXPECT_EQ(doc["fixtures"].size(), 2u);
  EXPECT_EQ(doc["hand"]["seed"], 3);

  const DrillRun protectedRun = drill(writePlan("into-the-slab", -11), "axis,depth,forbidden");
  ASSERT_EQ(protectedRun.Code, 0) << protectedRun.Err;
  doc = protectedRun.Json();
  EXPECT_FALSE(doc["enteredForbidden"].get<bool>());
  ASSERT_EQ(doc["clearance"].size(), 1u);
  EXPECT_GE(doc["clearance"][0]["closestMm"].get<double>(), 1.0 - 1e-6);
  EXPECT_LT(doc["depthErrorMm"].get<double>(), -1.0);  // held above the slab, short of its target

  // Bad input names the problem: no such file, a plan without a trajectory, an unknown fixture.
  EXPECT_EQ(drill((dir / "none.mrk.json").string(), "axis").Code, 1);
  const DrillRun unknown = drill(writePlan("tunnel", 0), "axis,laser");
  EXPECT_EQ(unknown.Code, 1);
  EXPECT_NE(unknown.Err.find("laser"), std::string::npos) << unknown.Err;
}
