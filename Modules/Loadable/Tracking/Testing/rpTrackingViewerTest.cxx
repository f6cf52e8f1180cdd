// Tracking in the viewer, through the scene and the displayable managers (the path the viewer
// draws with):
//  * the tracker unplugged in the middle of navigation (issue 18): the tool turns stale in the
//    views within the stale time, the driver reconnects by itself, nothing else in the scene
//    changes;
//  * an image stream (OpenIGTLink IMAGE, handed over as poses are) is shown in the slice views
//    and follows each new frame.
// Both write their measured figures to <test output>/*.json for the README table.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkActor.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkProperty.h>

#include "rpImageTable.h"
#include "rpResources.h"
#include "rpScreenshot.h"
#include "rpSimulatedPolaris.h"
#include "rpTrackingTestHelpers.h"
#include "rpTransformNames.h"
#include "rpView.h"
#include "rpViewController.h"
#include "rpViewerTestScene.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPToolDisplayableManager.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

using namespace rp;

namespace {

std::string OutputDir() {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return ROBOPLAN_TEST_OUTPUT_DIR;
}

void SavePng(vtkImageData* image, const std::string& name) {
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName((OutputDir() + "/" + name).c_str());
  writer->SetInputData(image);
  writer->Write();
}

// What the viewer's timer and the source's ready signal do: nodes updated at ~60 Hz.
template <class Condition>
bool Pump(vtkRPTrackingLogic* logic, Condition condition, double seconds) {
  const double end = SteadySeconds() + seconds;
  while (SteadySeconds() < end) {
    logic->UpdateNodes(SteadySeconds());
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
  }
  return false;
}

// Modification times of every node of the scene but the ones given.
std::map<std::string, vtkMTimeType> OtherNodeTimes(vtkRPScene* scene, const std::vector<std::string>& exceptIDs) {
  std::map<std::string, vtkMTimeType> times;
  for (vtkRPNode* node : scene->GetNodes())
    if (std::find(exceptIDs.begin(), exceptIDs.end(), node->GetID()) == exceptIDs.end())
      times[node->GetID() + " " + node->GetName()] = node->GetMTime();
  return times;
}

}  // namespace

TEST(TrackingInTheViewer, TrackerUnpluggedDuringNavigation) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  test::AddVolumeAndModel(scene);
  // TrackerToRAS puts the simulated stylus's pivot point at the centre of the volume.
  const ToolDefinition stylus = ReadToolDefinition(ResourcePath("Tools/Stylus.json"));
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;
  trackerToRAS->SetName(TransformName(TrackerFrameName, "RAS"));
  vtkNew<vtkMatrix4x4> m;
  for (int k = 0; k < 3; ++k) m->SetElement(k, 3, test::Center[k] - stylus.Motion.Center[k]);
  trackerToRAS->SetMatrixTransformToParent(m);
  scene->AddNode(trackerToRAS);

  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  logic->SetStaleTimeout(0.5);
  PolarisSimulator::Options simulator;
  simulator.LinkPath = OutputDir() + "/polaris";
  simulator.NoiseMm = 0.05;
  NdiTracker::Options driver;
  driver.ReconnectInitialSeconds = 0.1;
  driver.ReconnectMaxSeconds = 0.5;
  auto owned = std::make_unique<SimulatedPolaris>(simulator, std::vector<ToolDefinition>{stylus}, driver);
  SimulatedPolaris* source = owned.get();
  std::string error;
  ASSERT_GE(logic->AddSource(std::move(owned), error), 0) << error;

  const std::string name = ToolToTrackerName(stylus.Name);
  vtkRPTrackedToolNode* tool = nullptr;
  ASSERT_TRUE(Pump(logic, [&] {
    tool = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(name));
    return tool && tool->GetStatus() == vtkRPTrackedToolNode::StatusOK;
  }, 10)) << source->StatusText();
  // Navigation: the tool under TrackerToRAS, its calibrated tip under it, the slices following the tip.
  ASSERT_TRUE(tool->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  vtkNew<vtkRPLinearTransformNode> tip;
  tip->SetName(TransformName("StylusTip", stylus.Name));
  vtkNew<vtkMatrix4x4> tipOffset;
  for (int k = 0; k < 3; ++k) tipOffset->SetElement(k, 3, stylus.TipOffset[static_cast<size_t>(k)]);
  tip->SetMatrixTransformToParent(tipOffset);
  scene->AddNode(tip);
  ASSERT_TRUE(tip->SetAndObserveTransformNodeID(tool->GetID()));
  controller.SetFollowTransformNodeID(tip->GetID());
  auto* tools3D = controller.GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPToolDisplayableManager>();
  auto* toolsAxial = controller.GetView(ViewKind::Axial)->GetDisplayableManager<vtkRPToolDisplayableManager>();
  Pump(logic, [] { return false; }, 0.3);
  ASSERT_NE(tools3D->GetGlyphActor(tool), nullptr);
  EXPECT_DOUBLE_EQ(tools3D->GetGlyphActor(tool)->GetProperty()->GetOpacity(), 1.0);  // trusted: drawn solid
  ScreenshotOptions shot;
  shot.Width = shot.Height = 320;
  vtkNew<vtkImageData> tracking, stale;
  ASSERT_TRUE(RenderViews(controller, shot, tracking, error)) << error;
  SavePng(tracking, "navigating.png");

  // The cable comes out: the tool turns stale within the stale time (the poses it published
  // before the unplug still arrive first).
  const auto atUnplug = OtherNodeTimes(scene, {});
  const double unplugged = SteadySeconds();
  source->Simulator().Unplug();
  ASSERT_TRUE(Pump(logic, [&] { return tool->GetStatus() == vtkRPTrackedToolNode::StatusStale; }, 3));
  const double staleAfter = SteadySeconds() - unplugged;
  EXPECT_LE(staleAfter, logic->GetStaleTimeout() + 0.1);  // the stale time, a frame and an update
  EXPECT_LT(tools3D->GetGlyphActor(tool)->GetProperty()->GetOpacity(), 1.0);  // dimmed in 3D ...
  ASSERT_NE(toolsAxial->GetGlyphActor(tool), nullptr);
  EXPECT_LT(toolsAxial->GetGlyphActor(tool)->GetProperty()->GetOpacity(), 1.0);  // ... and on the slices
  ASSERT_TRUE(RenderViews(controller, shot, stale, error)) << error;
  SavePng(stale, "stale.png");
  EXPECT_FALSE(source->Connected());
  EXPECT_NE(source->StatusText().find("cannot open"), std::string::npos) << source->StatusText();  // retrying
  // The outage goes on (the driver retries with back-off): nothing in the scene changes, not
  // even the tool or the slices that follow it.
  const auto before = OtherNodeTimes(scene, {});
  double sliceRAS[3];
  controller.GetSlicePointRAS(sliceRAS);
  Pump(logic, [] { return false; }, 1.0);
  EXPECT_EQ(OtherNodeTimes(scene, {}), before) << "a node changed during the outage";
  double sliceNow[3];
  controller.GetSlicePointRAS(sliceNow);
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(sliceNow[k], sliceRAS[k]);
  EXPECT_EQ(tool->GetStatus(), vtkRPTrackedToolNode::StatusStale);

  // Plugged back in: the driver finds the device again by itself.
  ASSERT_TRUE(source->Simulator().Replug(error)) << error;
  const double replugged = SteadySeconds();
  ASSERT_TRUE(Pump(logic, [&] { return tool->GetStatus() == vtkRPTrackedToolNode::StatusOK; }, 10)) << source->StatusText();
  const double reconnectedAfter = SteadySeconds() - replugged;
  EXPECT_DOUBLE_EQ(tools3D->GetGlyphActor(tool)->GetProperty()->GetOpacity(), 1.0);
  EXPECT_EQ(source->Tracker().GetStatistics().Connections, 2u);
  // The data nodes are as they were (the tool and the slices move again: navigation).
  for (vtkRPNode* node : scene->GetNodes()) {
    if (!vtkRPScalarVolumeNode::SafeDownCast(node) && !vtkRPModelNode::SafeDownCast(node) && node != trackerToRAS.Get())
      continue;
    EXPECT_EQ(node->GetMTime(), atUnplug.at(node->GetID() + " " + node->GetName())) << node->GetName();
  }
  EXPECT_EQ(scene->GetNodesByClass("vtkRPTrackedToolNode").size(), 1u);  // the same tool node, not a second one
  std::ofstream(OutputDir() + "/unplug.json")
      << nlohmann::json{{"staleTimeoutSeconds", logic->GetStaleTimeout()}, {"staleAfterSeconds", staleAfter},
                        {"reconnectedAfterReplugSeconds", reconnectedAfter}}
             .dump(2);
  std::cout << "stale " << staleAfter << " s after the unplug (stale time " << logic->GetStaleTimeout()
            << " s); tracking again " << reconnectedAfter << " s after the replug\n";
}

TEST(TrackingInTheViewer, AnImageStreamIsShownInTheSliceViews) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  ToolPoseTable noPoses;
  ImageTable images;  // written below as the OpenIGTLink client writes it
  logic->AddPoseTable(&noPoses, &images);
  const int slot = images.FindOrAdd("USProbe", 7);
  // A 64 × 64 slice, 1 mm pixels, centred at the RAS origin: left half 40, right half 200.
  auto publish = [&](uint8_t left, uint8_t right) {
    ImageFrame& frame = images.BeginWrite(slot);
    frame.Dimensions[0] = frame.Dimensions[1] = 64;
    frame.Dimensions[2] = 1;
    frame.ScalarType = ImageFrame::UInt8;
    const double ijkToRas[16] = {1, 0, 0, -31.5, 0, 1, 0, -31.5, 0, 0, 1, 0, 0, 0, 0, 1};
    std::copy(ijkToRas, ijkToRas + 16, frame.IjkToRas);
    frame.ReceiveTime = SteadySeconds();
    frame.Pixels.resize(frame.ByteCount());
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) frame.Pixels[static_cast<size_t>(64 * j + i)] = i < 32 ? left : right;
    images.EndWrite(slot);
  };
  publish(40, 200);
  logic->UpdateNodes(SteadySeconds());
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(scene->GetFirstNodeByName("USProbe"));
  ASSERT_NE(volume, nullptr);
  EXPECT_EQ(controller.GetBackgroundVolume(), volume);  // the viewer shows it at once
  ScreenshotOptions shot;
  shot.Width = shot.Height = 200;
  shot.Layout = vtkRPLayoutNode::OneUpAxial;
  shot.HasSlicePoint = true;  // the slice through the image
  vtkNew<vtkImageData> first, second;
  std::string error;
  ASSERT_TRUE(RenderViews(controller, shot, first, error)) << error;
  // The two halves, on either side of the centre of the view.
  auto grey = [](vtkImageData* image, int x) { return static_cast<const uint8_t*>(image->GetScalarPointer(x, 100, 0))[0]; };
  const int a = grey(first, 60), b = grey(first, 140);
  EXPECT_GT(std::abs(a - b), 100) << a << " " << b;
  // The next frame: the halves swap; the node (the same one) follows.
  publish(200, 40);
  logic->UpdateNodes(SteadySeconds());
  EXPECT_EQ(scene->GetNodesByClass("vtkRPScalarVolumeNode").size(), 1u);
  ASSERT_TRUE(RenderViews(controller, shot, second, error)) << error;
  SavePng(first, "image-stream-1.png");
  SavePng(second, "image-stream-2.png");
  EXPECT_NEAR(grey(second, 60), b, 2);
  EXPECT_NEAR(grey(second, 140), a, 2);
  EXPECT_EQ(logic->GetImageStatistics().at(0).Shown, 2u);
}
