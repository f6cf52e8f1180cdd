// The main job end to end: `roboplan demo` on the small phantom, then its output folder read back
// with the conventions 3D Slicer documents (LPS in files, RAS in the scene, "from parent" ITK
// transforms), and the failure path (a bad --data folder: clear error, non-zero exit, what was
// done kept).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpAtomicFile.h"
#include "rpSceneIO.h"
#include "rpSharedData.h"
#include "rpTransformIO.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace {
std::string Roboplan;

// The figures of a demo run (report.json beside report.html).
nlohmann::json Figures(const fs::path& out) {
  std::string text, error;
  if (!rp::ReadFile((out / "report.json").string(), text, error)) return nlohmann::json::array();
  return nlohmann::json::parse(text)["figures"];
}
nlohmann::json FindFigure(const nlohmann::json& figures, const std::string& name) {
  for (const auto& f : figures)
    if (f["name"] == name) return f;
  return nullptr;
}

int RunRoboplan(const std::string& arguments, std::string& output) {
  const std::string command = Roboplan + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  output.clear();
  while (fgets(buffer, sizeof(buffer), pipe)) output += buffer;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST(Demo, SmallPhantomEndToEndAndSlicerConventions) {
  const fs::path out = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "demo";
  fs::remove_all(out);
  std::string output;
  const int code = RunRoboplan("demo --size small --haptic-seconds 2 --no-screenshots --out " + out.string(), output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("[demo 1/"), std::string::npos) << "progress lines on the terminal";
  ASSERT_TRUE(fs::exists(out / "report.html"));
  std::string report, error;
  ASSERT_TRUE(rp::ReadFile((out / "report.html").string(), report, error));
  EXPECT_NE(report.find("Figures and targets"), std::string::npos);
  EXPECT_EQ(report.find("failed</td>"), std::string::npos) << "every stage ran";
  // Every real bone of the phantom scored: Dice and surface distances to its true surface.
  // (Region growing merges the fibula into the tibia at this 1.6 mm size; the femur and patella
  // stand apart.)
  const auto figures = Figures(out);
  for (const char* bone : {"Femur", "Tibia", "Fibula", "Patella"}) {
    ASSERT_FALSE(FindFigure(figures, std::string(bone) + ": Dice").is_null()) << bone;
    EXPECT_FALSE(FindFigure(figures, std::string(bone) + ": mean surface distance to the true surface").is_null()) << bone;
    EXPECT_FALSE(FindFigure(figures, std::string(bone) + ": 95 % surface distance").is_null()) << bone;
  }
  for (const char* bone : {"Femur", "Patella"}) {
    EXPECT_GT(FindFigure(figures, std::string(bone) + ": Dice")["value"].get<double>(), 0.9) << bone;
    EXPECT_LT(FindFigure(figures, std::string(bone) + ": 95 % surface distance")["value"].get<double>(), 16.0) << bone;
  }

  // The scene opens with everything the workflow made.
  vtkNew<vtkRPScene> scene;
  const rp::SceneLoadReport loaded = rp::LoadScene(scene, (out / "scene.rpscene").string());
  ASSERT_TRUE(loaded.Ok) << loaded.Error;
  EXPECT_TRUE(loaded.Problems.empty()) << loaded.Problems.front();
  ASSERT_NE(scene->GetFirstNodeByName("CT"), nullptr);
  ASSERT_NE(scene->GetFirstNodeByName("MR"), nullptr);
  auto* mrToCT = vtkRPLinearTransformNode::SafeDownCast(scene->GetFirstNodeByName("MRToCT"));
  ASSERT_NE(mrToCT, nullptr);
  EXPECT_EQ(vtkRPScalarVolumeNode::SafeDownCast(scene->GetFirstNodeByName("MR"))->GetParentTransformNode(), mrToCT);
  EXPECT_GE(scene->GetNodesByClass("vtkRPSegmentationNode").size(), 1u);
  int bones = 0, haptic = 0;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    bones += model->GetTissueClass() == "bone";
    haptic += model->GetHaptic();
  }
  EXPECT_GE(bones, 4);
  EXPECT_GE(haptic, 4);
  auto* trackerToRAS = vtkRPLinearTransformNode::SafeDownCast(scene->GetFirstNodeByName("TrackerToRAS"));
  ASSERT_NE(trackerToRAS, nullptr);
  EXPECT_EQ(trackerToRAS->GetAttribute("Registration.Status"), "accepted");
  ASSERT_NE(scene->GetFirstNodeByName("StylusTipToStylus"), nullptr);

  // Fiducials: the .mrk.json holds LPS coordinates of the scene's RAS points (Slicer's default).
  auto* image = vtkRPFiducialListNode::SafeDownCast(scene->GetFirstNodeByName("ImageLandmarks"));
  ASSERT_NE(image, nullptr);
  ASSERT_GE(image->GetNumberOfControlPoints(), 4);
  std::string text;
  ASSERT_TRUE(rp::ReadFile((out / "ImageLandmarks.mrk.json").string(), text, error));
  const auto markups = nlohmann::json::parse(text);
  EXPECT_EQ(markups["markups"][0]["coordinateSystem"], "LPS");
  const auto& p0 = markups["markups"][0]["controlPoints"][0]["position"];
  double ras[3];
  image->GetNthControlPointPosition(0, ras);
  EXPECT_NEAR(p0[0].get<double>(), -ras[0], 1e-6);
  EXPECT_NEAR(p0[1].get<double>(), -ras[1], 1e-6);
  EXPECT_NEAR(p0[2].get<double>(), ras[2], 1e-6);

  // Transforms: the .tfm holds the "from parent" matrix in LPS: S · inverse(toParent) · S.
  ASSERT_TRUE(rp::ReadFile((out / "TrackerToRAS.tfm").string(), text, error));
  EXPECT_NE(text.find("#Insight Transform File V1.0"), std::string::npos);
  std::istringstream lines(text);
  std::string line;
  std::vector<double> parameters;
  while (std::getline(lines, line)) {
    if (line.rfind("Parameters:", 0) == 0) {
      std::istringstream values(line.substr(11));
      double v;
      while (values >> v) parameters.push_back(v);
    }
  }
  ASSERT_EQ(parameters.size(), 12u);
  vtkNew<vtkMatrix4x4> fromParent;
  vtkMatrix4x4::Invert(trackerToRAS->GetMatrixTransformToParent(), fromParent);
  const double s[3] = {-1, -1, 1};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(parameters[3 * r + c], s[r] * fromParent->GetElement(r, c) * s[c], 1e-9);

  // Models carry Slicer's coordinate-system tag; the segmentation is a .seg.nrrd with Slicer keys.
  ASSERT_TRUE(rp::ReadFile((out / "KneeSegmentation.seg.nrrd").string(), text, error));
  EXPECT_NE(text.find("Segment0_LabelValue:="), std::string::npos);
  EXPECT_NE(text.find("space: left-posterior-superior"), std::string::npos);

  // Logs committed at the end of the session.
  EXPECT_TRUE(fs::exists(out / "haptics-bone.csv"));
  EXPECT_TRUE(fs::exists(out / "tracking-pivot.txt"));
  EXPECT_TRUE(fs::exists(out / "tracking-navigation.txt"));
  EXPECT_TRUE(fs::exists(out / "registration-log.txt"));
  EXPECT_TRUE(fs::exists(out / "dicom" / "CT"));
}

TEST(Demo, ARealKneeCTIsScoredPerBoneAgainstItsLabels) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/labels.nrrd");
  const fs::path out = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "demo-vhf";
  fs::remove_all(out);
  fs::create_directories(out);
  // Names for the label values (Slicer colour table), as the data's README gives them.
  const fs::path names = out / "labels.ctbl";
  std::ofstream(names) << "# knee-ct-vhf\n1 tibia 128 174 128 255\n2 fibula 241 214 145 255\n3 patella 177 122 101 255\n";
  const std::string data = rptest::SharedDataPath("knee-ct-vhf");
  std::string output;
  const int code = RunRoboplan("demo --haptic-seconds 1 --no-screenshots --data " + data + "/dicom --truth " + data +
                                   "/labels.nrrd --truth-names " + names.string() + " --out " + (out / "run").string(),
                               output);
  ASSERT_EQ(code, 0) << output;
  const auto figures = Figures(out / "run");
  for (const char* bone : {"tibia", "fibula", "patella"}) {
    const auto dice = FindFigure(figures, std::string(bone) + ": Dice");
    ASSERT_FALSE(dice.is_null()) << bone << " not scored";
    EXPECT_NE(dice["result"], "not scored") << bone;
    EXPECT_FALSE(FindFigure(figures, std::string(bone) + ": mean surface distance to the truth label's surface").is_null())
        << bone;
  }
  // The tibia is found (a bone segment overlaps it); how well is the segmentation's figure.
  EXPECT_GT(FindFigure(figures, "tibia: Dice")["value"].get<double>(), 0.3);
  // --truth without --data is a usage error.
  EXPECT_EQ(RunRoboplan("demo --truth " + data + "/labels.nrrd --out " + (out / "x").string(), output), 2);
  EXPECT_NE(output.find("--truth"), std::string::npos) << output;
}

TEST(Demo, ABadDataFolderFailsClearlyAndKeepsTheReport) {
  const fs::path out = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "demo-bad";
  fs::remove_all(out);
  const fs::path empty = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "no-dicom-here";
  fs::create_directories(empty);
  std::ofstream(empty / "notes.txt") << "not a DICOM file";
  std::string output;
  const int code = RunRoboplan("demo --no-screenshots --data " + empty.string() + " --out " + out.string(), output);
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("FAILED"), std::string::npos) << output;
  EXPECT_NE(output.find("no loadable image series"), std::string::npos) << output;
  EXPECT_TRUE(fs::exists(out / "report.html"));
  EXPECT_TRUE(fs::exists(out / "scene.rpscene"));
  EXPECT_EQ(RunRoboplan("demo --size huge --out " + out.string(), output), 1);
  EXPECT_EQ(RunRoboplan("demo --bogus", output), 2);
  EXPECT_NE(output.find("unknown option '--bogus'"), std::string::npos);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: rpDemoSystemTest <path to roboplan>\n");
    return 2;
  }
  Roboplan = argv[1];
  return RUN_ALL_TESTS();
}
