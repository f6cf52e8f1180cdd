// Pivot calibration recovers a known tip offset (the Stylus tool definition), with a known RMSE
// for a known noise; rejection above the threshold; ToolToReference; recording round trip and
// the `roboplan pivot` command on a recording.
#include <gtest/gtest.h>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "rpPivotCalibration.h"
#include "rpToolDefinition.h"
#include "rpTrackingCommands.h"
#include "rpTrackingRecording.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

using namespace rp;

namespace {
ToolDefinition Stylus() { return ReadToolDefinition(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/Stylus.json"); }

std::vector<ToolPose> PivotPoses(const ToolDefinition& tool, int count, double noiseMm, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0, noiseMm);
  std::vector<ToolPose> poses;
  for (int i = 0; i < count; ++i) {
    double m[16];
    EvaluateTrajectory(tool, i * 0.05, m);
    ToolPose p;
    p.FromMatrix(m);
    if (noiseMm > 0)
      for (double& v : p.Translation) v += gauss(rng);
    p.State = ToolState::OK;
    poses.push_back(p);
  }
  return poses;
}
std::string OutputDir() {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return ROBOPLAN_TEST_OUTPUT_DIR;
}
}  // namespace

TEST(PivotCalibration, RecoversTheStylusTipExactlyWithoutNoise) {
  const ToolDefinition stylus = Stylus();
  const PivotResult r = PivotCalibrate(PivotPoses(stylus, 200, 0, 1));
  ASSERT_TRUE(r.Valid) << r.Message;
  EXPECT_TRUE(r.Accepted);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.TipOffset[k], stylus.TipOffset[k], 1e-6);
    EXPECT_NEAR(r.PivotPoint[k], stylus.Motion.Center[k], 1e-6);
  }
  EXPECT_LT(r.Rmse, 1e-6);
  EXPECT_GT(r.RotationSpreadDeg, 15.0);
}

// The Tracking logic's calibration (the panel's, `pivot`'s and the demo's): StylusTipToStylus
// under the stylus node, the tip offset as its translation, the RMSE as its attribute.
TEST(PivotCalibration, TheLogicAppliesTheTipUnderTheStylus) {
  const ToolDefinition stylus = Stylus();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackedToolNode> stylusNode;
  stylusNode->SetName("StylusToTracker");
  scene->AddNode(stylusNode);
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  vtkRPLinearTransformNode* tip = nullptr;
  const PivotResult r = logic->CalibratePivot(PivotPoses(stylus, 200, 0, 1), "StylusToTracker", 1.0, 10.0, &tip);
  ASSERT_TRUE(r.Accepted) << r.Message;
  ASSERT_NE(tip, nullptr);
  EXPECT_EQ(tip->GetName(), "StylusTipToStylus");
  EXPECT_EQ(tip->GetTransformNodeID(), stylusNode->GetID());
  vtkMatrix4x4* m = tip->GetMatrixTransformToParent();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(m->GetElement(k, 3), stylus.TipOffset[k], 1e-6);
  EXPECT_EQ(tip->GetAttribute(vtkRPTrackingLogic::PivotCalibrationRMSEAttribute()), std::to_string(r.Rmse));
  // Too few poses: not solved, nothing applied; without a scene nothing is applied either.
  const int nodes = scene->GetNumberOfNodes();
  EXPECT_FALSE(logic->CalibratePivot(PivotPoses(stylus, 4, 0, 1), "StylusToTracker", 1.0, 10.0, &tip).Valid);
  EXPECT_EQ(tip, nullptr);
  vtkNew<vtkRPTrackingLogic> sceneless;
  EXPECT_TRUE(sceneless->CalibratePivot(PivotPoses(stylus, 200, 0, 1), "StylusToTracker", 1.0, 10.0, &tip).Valid);
  EXPECT_EQ(tip, nullptr);
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
}

TEST(PivotCalibration, RmseMatchesTheNoiseModel) {
  // Isotropic noise sigma per axis on the translation: residual RMS -> sigma*sqrt(3*(1-6/(3N)))
  // (6 unknowns fitted from 3N equations).
  const ToolDefinition stylus = Stylus();
  const double sigma = 0.25;
  const int n = 2000;
  const PivotResult r = PivotCalibrate(PivotPoses(stylus, n, sigma, 7), 1.0);
  ASSERT_TRUE(r.Valid) << r.Message;
  const double expected = sigma * std::sqrt(3.0 * (1.0 - 6.0 / (3.0 * n)));
  EXPECT_NEAR(r.Rmse, expected, 0.03 * expected);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.TipOffset[k], stylus.TipOffset[k], 0.1);
  EXPECT_TRUE(r.Accepted);
  const PivotResult strict = PivotCalibrate(PivotPoses(stylus, n, sigma, 7), 0.2);
  EXPECT_TRUE(strict.Valid);
  EXPECT_FALSE(strict.Accepted);
  EXPECT_NE(strict.Message.find("exceeds the threshold"), std::string::npos);
}

TEST(PivotCalibration, DegenerateInputsAreRefused) {
  const ToolDefinition stylus = Stylus();
  EXPECT_FALSE(PivotCalibrate(PivotPoses(stylus, 4, 0, 1)).Valid);
  std::vector<ToolPose> still(50, PivotPoses(stylus, 1, 0, 1)[0]);  // never rotates
  const PivotResult r = PivotCalibrate(still);
  EXPECT_FALSE(r.Valid);
  EXPECT_NE(r.Message.find("did not rotate enough"), std::string::npos);
  auto missing = PivotPoses(stylus, 100, 0, 1);
  for (auto& p : missing) p.State = ToolState::Missing;
  EXPECT_EQ(PivotCalibrate(missing).PosesUsed, 0u);
}

TEST(PivotCalibration, ToolToReferenceInvertsTheReference) {
  ToolPose tool, reference;
  const double half = std::sqrt(0.5);
  reference.Quaternion[0] = half;  // 90 deg about z
  reference.Quaternion[3] = half;
  reference.Translation[0] = 100;
  tool.Translation[0] = 100;
  tool.Translation[1] = 50;  // 50 mm along tracker y from the reference origin
  tool.State = reference.State = ToolState::OK;
  const ToolPose rel = ToolToReference(tool, reference);
  // Reference x axis points along tracker y: the tool is at +50 along reference x.
  EXPECT_NEAR(rel.Translation[0], 50, 1e-9);
  EXPECT_NEAR(rel.Translation[1], 0, 1e-9);
  EXPECT_NEAR(std::abs(rel.Quaternion[0]), half, 1e-9);
  reference.State = ToolState::Missing;
  EXPECT_EQ(ToolToReference(tool, reference).State, ToolState::Missing);
}

TEST(PivotCalibration, RecordingRoundTripAndPivotCommand) {
  const ToolDefinition stylus = Stylus();
  Recording rec;
  rec.Tools = {"Stylus", "Reference"};
  const auto poses = PivotPoses(stylus, 300, 0.1, 3);
  for (size_t i = 0; i < poses.size(); ++i) {
    Recording::Sample s;
    s.Time = i / 60.0;
    s.Tool = 0;
    s.Pose = poses[i];
    s.Pose.Frame = static_cast<uint32_t>(i + 1);
    rec.Samples.push_back(s);
    Recording::Sample r;
    r.Time = s.Time;
    r.Tool = 1;
    r.Pose.State = ToolState::OK;  // identity reference: ToolToReference = ToolToTracker
    rec.Samples.push_back(r);
  }
  const std::string path = OutputDir() + "/pivot.rec";
  rec.Write(path);
  const Recording back = Recording::Read(path);
  ASSERT_EQ(back.Samples.size(), rec.Samples.size());
  EXPECT_EQ(back.Tools, rec.Tools);
  EXPECT_NEAR(back.Samples[10].Pose.Translation[2], rec.Samples[10].Pose.Translation[2], 1e-6);
  EXPECT_EQ(back.Samples[10].Pose.Frame, rec.Samples[10].Pose.Frame);

  std::ostringstream out, err;
  ASSERT_EQ(RunPivotCommand({path, "--reference", "Reference", "--json"}, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("\"accepted\": true"), std::string::npos) << out.str();
  std::ostringstream out2, err2;
  EXPECT_EQ(RunPivotCommand({path, "--threshold", "0.01"}, out2, err2), 1);
  EXPECT_NE(err2.str().find("exceeds the threshold"), std::string::npos);
  std::ostringstream out3, err3;
  EXPECT_EQ(RunPivotCommand({OutputDir() + "/absent.rec"}, out3, err3), 1);
  EXPECT_NE(err3.str().find("cannot open recording"), std::string::npos);
  std::ostringstream out4, err4;
  EXPECT_EQ(RunPivotCommand({}, out4, err4), 2);
  {
    std::ofstream bad(OutputDir() + "/bad.rec");
    bad << "# RoboPlan tracking recording 1\n0.0 Stylus OK 1 0 0\n";
  }
  std::ostringstream out5, err5;
  EXPECT_EQ(RunPivotCommand({OutputDir() + "/bad.rec"}, out5, err5), 1);
  EXPECT_NE(err5.str().find("bad.rec:2: expected 12 fields"), std::string::npos) << err5.str();
}

TEST(TrackingRecording, ReplayPublishesAtTheRecordedPace) {
  Recording rec;
  rec.Tools = {"Stylus", "Reference"};
  for (int i = 0; i < 60; ++i) {  // one second at 60 Hz
    Recording::Sample s;
    s.Time = 5.0 + i / 60.0;
    s.Tool = i % 2;
    s.Pose.State = ToolState::OK;
    s.Pose.Translation[0] = i;
    s.Pose.Frame = static_cast<uint32_t>(i);
    rec.Samples.push_back(s);
  }
  RecordingPlayer player(rec, /*speed=*/4.0);
  const double start = SteadySeconds();
  player.Start();
  while (!player.Finished() && SteadySeconds() - start < 5) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const double elapsed = SteadySeconds() - start;
  ASSERT_TRUE(player.Finished());
  EXPECT_NEAR(elapsed, (59 / 60.0) / 4.0, 0.1);  // 4x speed
  ASSERT_EQ(player.Poses().Count(), 2);
  ToolPose last;
  EXPECT_EQ(player.Poses().Read(0, last), 30u);  // every Stylus pose published
  EXPECT_DOUBLE_EQ(last.Translation[0], 58.0);
  EXPECT_EQ(player.Poses().Read(1, last), 30u);
  EXPECT_DOUBLE_EQ(last.Translation[0], 59.0);
}
