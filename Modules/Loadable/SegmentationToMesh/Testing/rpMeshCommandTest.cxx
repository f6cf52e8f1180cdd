// `roboplan mesh` end to end: a CT volume file with a known ball → segmentation file + closed
// surfaces with the ball's volume; a .seg.nrrd as input; bad arguments (exit 2) and a leaking
// threshold (exit 1, message on stderr).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <sys/wait.h>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpLabelmapToMesh.h"
#include "rpModelIO.h"
#include "rpSegmentationIO.h"
#include "rpSharedData.h"
#include "rpTestOutput.h"
#include "rpVolumeIO.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

using rptest::TestDir;

namespace {

struct CommandRun {
  int Code = -1;
  std::string Out, Err;
};

CommandRun Roboplan(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string command = std::string(ROBOPLAN_BINARY_DIR) + "/bin/roboplan " + args + " 2> " + err.string();
  CommandRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) run.Out.append(buffer, n);
  const int status = pclose(pipe);
  run.Code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err);
  std::stringstream ss;
  ss << in.rdbuf();
  run.Err = ss.str();
  return run;
}

constexpr double Radius = 9.0;

// CT: air -1000 HU with a 1000 HU ball (partial volume from 4x4x4 subsamples), 1 x 1 x 1.5 mm.
fs::path WriteBallCT(const fs::path& dir) {
  vtkNew<vtkRPScalarVolumeNode> ct;
  vtkNew<vtkImageData> image;
  image->SetDimensions(32, 32, 24);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  const double c[3] = {15.3, 16.1, 17.2};
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i) {
        int inside = 0;
        for (int s = 0; s < 64; ++s) {
          const double x = i + (s % 4 - 1.5) / 4, y = j + ((s / 4) % 4 - 1.5) / 4, z = (k + (s / 16 - 1.5) / 4) * 1.5;
          inside += (x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]) < Radius * Radius;
        }
        *v++ = static_cast<short>(-1000 + 2000 * inside / 64);
      }
  ct->SetImageData(image);
  const double spacing[3] = {1, 1, 1.5}, origin[3] = {0, 0, 0}, directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ct->SetGeometry(spacing, origin, directions);
  const fs::path path = dir / "ball.nrrd";
  std::string error;
  EXPECT_TRUE(rp::WriteVolumeFile(path.string(), ct, error)) << error;
  return path;
}

}  // namespace

TEST(MeshCommand, VolumeToSegmentationAndClosedSurfacesWithJsonStats) {
  const fs::path dir = TestDir("volume");
  const fs::path ct = WriteBallCT(dir);
  const CommandRun run = Roboplan("mesh " + ct.string() + " --out " + (dir / "out").string() +
                               " --preset bone --lower 0 --keep-largest --fill-holes --haptic-triangles 500 --json",
                           dir);
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = nlohmann::json::parse(run.Out, nullptr, false);
  ASSERT_TRUE(doc.is_object()) << run.Out;
  ASSERT_EQ(doc["segments"].size(), 1u);
  const auto& bone = doc["segments"][0];
  EXPECT_EQ(bone["id"], "bone");
  EXPECT_EQ(bone["tissueClass"], "bone");
  EXPECT_TRUE(bone["display"]["watertight"].get<bool>());
  EXPECT_TRUE(bone["haptic"]["watertight"].get<bool>());
  EXPECT_LE(bone["haptic"]["triangles"].get<long>(), 500);
  const double truth = 4.0 / 3.0 * 3.14159265358979 * Radius * Radius * Radius;
  EXPECT_NEAR(bone["display"]["meshVolumeMm3"].get<double>(), truth, 0.02 * truth);

  vtkNew<vtkPolyData> mesh;
  std::string error;
  ASSERT_TRUE(rp::ReadModelFile(bone["display"]["file"].get<std::string>(), mesh, error)) << error;
  double volume = 0, area = 0;
  rp::MeshVolumeAndArea(mesh, volume, area);
  EXPECT_NEAR(volume, truth, 0.02 * truth);

  // The segmentation was written as Slicer's .seg.nrrd and meshes again as input.
  const fs::path seg = dir / "out" / "segmentation.seg.nrrd";
  ASSERT_TRUE(fs::exists(seg));
  vtkNew<vtkRPSegmentationNode> node;
  ASSERT_TRUE(rp::ReadSegmentationFile(seg.string(), node, error)) << error;
  ASSERT_EQ(node->GetNumberOfSegments(), 1);
  EXPECT_EQ(node->GetNthSegment(0).TissueClass, "bone");
  const CommandRun again = Roboplan("mesh " + seg.string() + " --out " + (dir / "again").string() +
                                 " --mesh-method sinc --no-haptic --format stl",
                             dir);
  ASSERT_EQ(again.Code, 0) << again.Err;
  EXPECT_TRUE(fs::exists(dir / "again" / "bone.stl"));
  EXPECT_NE(again.Err.find("[mesh]"), std::string::npos) << "progress lines on stderr";
}

TEST(MeshCommand, BadArgumentsAndLeaksGiveClearErrors) {
  const fs::path dir = TestDir("bad");
  const fs::path ct = WriteBallCT(dir);
  CommandRun run = Roboplan("mesh " + ct.string() + " --out " + (dir / "o").string() + " --grid-step 0", dir);
  EXPECT_EQ(run.Code, 2);
  EXPECT_NE(run.Err.find("grid-step"), std::string::npos) << run.Err;
  run = Roboplan("mesh " + ct.string() + " --out " + (dir / "o").string() + " --method region-grow", dir);
  EXPECT_EQ(run.Code, 2);
  EXPECT_NE(run.Err.find("--seed"), std::string::npos) << run.Err;
  run = Roboplan("mesh " + ct.string() + " --out " + (dir / "o").string() + " --preset marrow", dir);
  EXPECT_EQ(run.Code, 2);
  EXPECT_NE(run.Err.find("marrow"), std::string::npos) << run.Err;
  // A threshold below air selects the whole volume: refused as a leak.
  run = Roboplan("mesh " + ct.string() + " --out " + (dir / "o").string() + " --lower -3000", dir);
  EXPECT_EQ(run.Code, 1);
  EXPECT_NE(run.Err.find("leaked"), std::string::npos) << run.Err;
  run = Roboplan("mesh " + (dir / "missing.nrrd").string() + " --out " + (dir / "o").string(), dir);
  EXPECT_EQ(run.Code, 1);
  EXPECT_NE(run.Err.find("missing.nrrd"), std::string::npos) << run.Err;
  // Region growing from a seed in the ball works.
  run = Roboplan("mesh " + ct.string() + " --out " + (dir / "grow").string() +
                     " --method region-grow --seed 15,16,17 --lower 0 --no-haptic --grid-mm 1.5 --json",
                 dir);
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = nlohmann::json::parse(run.Out, nullptr, false);
  ASSERT_TRUE(doc.is_object());
  const auto& display = doc["segments"][0]["display"];
  EXPECT_TRUE(display["watertight"].get<bool>());
  // 1.5 mm grid on 1 x 1 x 1.5 mm voxels: steps 1.5, 1.5, 1.
  EXPECT_DOUBLE_EQ(display["gridStep"][0].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(display["gridStep"][2].get<double>(), 1.0);
  run = Roboplan("mesh " + ct.string() + " --out " + (dir / "o").string() + " --grid-mm -1", dir);
  EXPECT_EQ(run.Code, 2);
}

TEST(MeshCommand, RealNiftiFileFromAnotherWriter) {
  // The Pac-Man volume of shared/data (128³, 1 mm, doubles 0/1/2): label 2 has 677196 voxels
  // (counted independently from the file's histogram) and is one closed object.
  RP_REQUIRE_SHARED_DATA("pacsman.nii.gz");
  const fs::path nifti = rptest::SharedDataPath("pacsman.nii.gz");
  const fs::path dir = TestDir("nifti");
  const CommandRun run = Roboplan("mesh " + nifti.string() + " --out " + (dir / "out").string() +
                                      " --lower 1.5 --upper 2.5 --max-fraction 0.5 --no-haptic --json",
                                  dir);
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = nlohmann::json::parse(run.Out, nullptr, false);
  ASSERT_TRUE(doc.is_object()) << run.Out;
  const auto& display = doc["segments"][0]["display"];
  EXPECT_EQ(display["labelVoxels"].get<long>(), 677196);
  EXPECT_NEAR(display["labelVolumeMm3"].get<double>(), 677196.0, 1.0);
  EXPECT_TRUE(display["watertight"].get<bool>());
  EXPECT_LT(std::abs(display["volumeErrorPercent"].get<double>()), 0.1);
}

TEST(MeshCommand, SplitBonesOfTheRealKneeCTWithTruth) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf");
  const fs::path knee = rptest::SharedDataPath("knee-ct-vhf");
  const fs::path dir = TestDir("split-bones");
  const CommandRun run = Roboplan("mesh " + (knee / "dicom").string() + " --out " + (dir / "out").string() +
                                      " --split-bones --truth " + (knee / "labels.nrrd").string() +
                                      " --bone-seed -160,-308,420:fibula --no-haptic --json",
                                  dir);
  ASSERT_EQ(run.Code, 0) << run.Err;
  const auto doc = nlohmann::json::parse(run.Out, nullptr, false);
  ASSERT_TRUE(doc.is_object()) << run.Out;
  std::map<std::string, nlohmann::json> bones;
  for (const auto& b : doc["boneSplit"]["bones"]) bones[b["id"].get<std::string>()] = b;
  ASSERT_TRUE(bones.count("tibia") && bones.count("fibula")) << doc["boneSplit"].dump();
  EXPECT_EQ(bones["fibula"]["namedBy"], "seed");
  EXPECT_EQ(bones["tibia"]["namedBy"], "knee anatomy");
  for (const auto& score : doc["truth"]) {
    if (score["segment"] == "tibia") {
      EXPECT_EQ(score["truthLabel"], 1);
      EXPECT_GT(score["dice"].get<double>(), 0.93);
    }
    if (score["segment"] == "fibula") {
      EXPECT_EQ(score["truthLabel"], 2);
    }
  }
  for (const auto& s : doc["segments"]) EXPECT_TRUE(s["display"]["watertight"].get<bool>()) << s["id"];
  EXPECT_TRUE(fs::exists(dir / "out" / "tibia.vtp"));
  EXPECT_TRUE(fs::exists(dir / "out" / "segmentation.seg.nrrd"));
  // A seed off bone: exit 1 naming it.
  const CommandRun off = Roboplan("mesh " + (knee / "dicom").string() + " --out " + (dir / "off").string() +
                                      " --split-bones --bone-seed 0,0,0:nothing",
                                  dir);
  EXPECT_EQ(off.Code, 1);
  EXPECT_NE(off.Err.find("'nothing' is not on bone"), std::string::npos) << off.Err;
}

// The one loader gives `mesh` what `convert` has: a folder holding two DICOM series is refused
// naming them, and --series picks one (the ball's CT written twice, as CT and as MR).
TEST(MeshCommand, DicomFolderWithTwoSeriesNeedsSeries) {
  const fs::path dir = TestDir("two-series");
  const fs::path ct = WriteBallCT(dir);
  for (const char* modality : {"CT", "MR"}) {
    const CommandRun convert = Roboplan("convert " + ct.string() + " " + (dir / "dicom" / modality).string() +
                                            " --modality " + modality, dir);
    ASSERT_EQ(convert.Code, 0) << convert.Err;
  }
  const CommandRun list = Roboplan("dicom " + (dir / "dicom").string() + " --json", dir);
  ASSERT_EQ(list.Code, 0) << list.Err;
  const auto series = nlohmann::json::parse(list.Out)["series"];
  ASSERT_EQ(series.size(), 2u) << list.Out;
  std::string mrID;
  for (const auto& s : series)
    if (s["modality"] == "MR") mrID = s["id"];
  ASSERT_FALSE(mrID.empty()) << list.Out;

  const CommandRun refused = Roboplan("mesh " + (dir / "dicom").string() + " --out " + (dir / "o1").string(), dir);
  EXPECT_EQ(refused.Code, 1);
  EXPECT_NE(refused.Err.find("series"), std::string::npos) << refused.Err;

  const CommandRun chosen = Roboplan("mesh " + (dir / "dicom").string() + " --series " + mrID + " --out " +
                                         (dir / "o2").string() + " --preset bone --lower 0 --no-haptic --json", dir);
  ASSERT_EQ(chosen.Code, 0) << chosen.Err;
  const auto doc = nlohmann::json::parse(chosen.Out);
  ASSERT_EQ(doc["segments"].size(), 1u) << chosen.Out;
  const double volume = doc["segments"][0]["display"]["meshVolumeMm3"];
  const double expected = 4.0 / 3.0 * 3.14159265358979 * Radius * Radius * Radius;  // the ball, as above
  EXPECT_NEAR(volume, expected, 0.02 * expected);
}
