// The Haptics panel on a flat bone slab: start the simulated device, press the stylus into the
// top face with the spin boxes, and read the force, tissue and penetration back from the panel.
// Known answers: force = k·depth (k of bone from Resources/Materials/materials.json) below the
// device's force limit, and the limit (3.3 N, seed eq. 6) above it; on the Touch (0.4 N/mm) bone
// is clamped to 0.4 N/mm with a warning in the panel.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QPushButton>
#include <QThread>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "qRPFixtureChoiceWidget.h"
#include "qRPHapticsPanel.h"
#include "rpFixtureSet.h"
#include "rpHapticsGuidanceScene.h"
#include "qRPSliceFollowCheckBox.h"
#include "rpHapticSceneBridge.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpHapticSession.h"
#include "rpSimulatedDevice.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrajectoryNode.h"
#ifdef ROBOPLAN_TEST_WITH_VIEWER
#include <vtkImageData.h>
#include "rpScreenshot.h"
#include "rpViewController.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPSliceLogic.h"
#endif

namespace {
double BoneStiffness() {
  std::ifstream in(std::string(ROBOPLAN_RESOURCES_DIR) + "/Materials/materials.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  for (const auto& m : doc.at("materials"))
    if (m.at("tissue") == "bone") return m.at("stiffness").get<double>();
  return -1;
}

// The display timer's work for `seconds` (the test drives it: 10 ms steps).
void Pump(QApplication& app, qRPHapticsPanel& panel, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    app.processEvents();
    panel.Update();
    QThread::msleep(10);
  }
}
}  // namespace

TEST(HapticsPanel, PressIntoBoneSlabShowsStiffnessForceAndTissue) {
  int argc = 1;
  char name[] = "qRPHapticsPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPModelNode> slab;  // top face at S = 0
  slab->SetName("Slab");
  slab->SetTissueClass("bone");
  slab->SetHaptic(true);
  slab->SetPolyData(rp::TriangleMeshToPolyData(rp::shapes::Box({-40, -40, -20}, {40, 40, 0})));
  scene->AddNode(slab);
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  const std::string log = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/haptics-panel-session.csv";
  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  std::remove(log.c_str());
  const double k = BoneStiffness();
  ASSERT_GT(k, 0);

  auto panel = std::make_unique<qRPHapticsPanel>(logic.GetPointer());
  panel->LogPathEdit()->setText(QString::fromStdString(log));
  panel->show();
  // Spin box ranges: the haptic models' bounds ± 20 mm.
  EXPECT_DOUBLE_EQ(panel->StylusSpinBox(2)->minimum(), -40);
  EXPECT_DOUBLE_EQ(panel->StylusSpinBox(2)->maximum(), 20);
  auto pump = [&](double seconds) { Pump(app, *panel, seconds); };
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  panel->StylusSpinBox(0)->setValue(3);
  panel->StylusSpinBox(1)->setValue(-4);
  pump(0.6);  // past the 0.5 s force ramp, stylus above the slab
  EXPECT_EQ(panel->TissueText(), "none");
  EXPECT_NEAR(panel->DisplayedForce(), 0, 1e-9);

  // 1 mm into the top face: F = k·1 mm (2 N for bone, under the device limit).
  panel->StylusSpinBox(2)->setValue(-1);
  pump(0.3);
  EXPECT_EQ(panel->TissueText(), "bone");
  EXPECT_NEAR(panel->DisplayedForce(), k * 1.0, 0.15 * k * 1.0) << panel->ForceText().toStdString();
  EXPECT_EQ(panel->PenetrationText(), "1.00 mm");
  std::printf("1 mm into bone: %s (k = %.2f N/mm), servo p99 period / compute %s\n",
              panel->ForceText().toStdString().c_str(), k, panel->TimingText().toStdString().c_str());

  // The default device is the Phantom Omni, which renders bone as the table asks: no warning.
  EXPECT_EQ(panel->DeviceComboBox()->currentData().toString(), "omni");
  EXPECT_FALSE(panel->DeviceComboBox()->isEnabled());  // not while running
  EXPECT_TRUE(panel->ClampText().isEmpty()) << panel->ClampText().toStdString();

  // 5 mm: k·5 mm exceeds the Omni's 3.3 N; the renderer clamps to it (eq. 6).
  panel->StylusSpinBox(2)->setValue(-5);
  pump(0.3);
  EXPECT_EQ(panel->TissueText(), "bone");
  const double limit = rp::SimulatedDevice::DefaultInfo().MaxForce;
  ASSERT_GT(k * 5.0, limit);
  EXPECT_NEAR(panel->DisplayedForce(), limit, 0.05 * limit) << panel->ForceText().toStdString();
  std::printf("5 mm into bone: %s (limit %.1f N)\n", panel->ForceText().toStdString().c_str(), limit);
  EXPECT_TRUE(panel->TimingText().endsWith("us")) << panel->TimingText().toStdString();

  // The Touch renders at most 0.4 N/mm: bone is clamped, the panel says so, 1 mm gives 0.4 N.
  panel->StartStopButton()->click();
  ASSERT_FALSE(panel->IsRunning());
  panel->DeviceComboBox()->setCurrentIndex(panel->DeviceComboBox()->findData("touch"));
  panel->StylusSpinBox(2)->setValue(10);
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  EXPECT_EQ(logic->GetDeviceProfile(), "touch");
  pump(0.6);
  panel->StylusSpinBox(2)->setValue(-1);
  pump(0.3);
  const double touchK = std::min(k, 0.4);
  EXPECT_NEAR(panel->DisplayedForce(), touchK * 1.0, 0.15 * touchK) << panel->ForceText().toStdString();
  if (k > 0.4) {
    EXPECT_NE(panel->ClampText().indexOf("bone: " + QString::number(k, 'f', 2) + " → 0.40 N/mm"), -1)
        << panel->ClampText().toStdString();
    bool warned = false;
    for (const auto& w : logic->GetSession()->Warnings()) warned |= w.rfind("bone: stiffness", 0) == 0;
    EXPECT_TRUE(warned);
  }
  std::printf("Touch, 1 mm into bone: %s; %s\n", panel->ForceText().toStdString().c_str(),
              panel->ClampText().toStdString().c_str());

  // Closing the panel stops the loop and commits the session log.
  panel.reset();
  EXPECT_FALSE(logic->IsRunning());
  double force[3];
  logic->GetLastForce(force);  // the device was left with zero force
  EXPECT_EQ(force[0], 0.0);
  EXPECT_EQ(force[1], 0.0);
  EXPECT_EQ(force[2], 0.0);
  std::ifstream in(log);
  ASSERT_TRUE(in.good()) << log;
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_GT(lines, 500);  // ~1.2 s at 1 kHz
}

// The panel drives the views through the scene only: "Slices follow the haptic proxy" makes the
// scene's slice nodes follow the HapticProxy node, so the slices pass through the point of
// contact as the stylus moves; with a viewer on the scene, the rendered axial slice moves too.
TEST(HapticsPanel, SlicesFollowTheProxyThroughTheScene) {
  int argc = 1;
  char name[] = "qRPHapticsPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPModelNode> slab;  // top face at S = 0
  slab->SetName("Slab");
  slab->SetTissueClass("bone");
  slab->SetHaptic(true);
  slab->SetPolyData(rp::TriangleMeshToPolyData(rp::shapes::Box({-40, -40, -20}, {40, 40, 0})));
  scene->AddNode(slab);
  // A volume whose value is 100 × S (mm): the grey of the axial slice says where it is.
  vtkNew<vtkImageData> image;
  image->SetDimensions(41, 41, 61);
  image->AllocateScalars(VTK_FLOAT, 1);
  for (int k = 0; k < 61; ++k)
    for (int j = 0; j < 41; ++j)
      for (int i = 0; i < 41; ++i) *static_cast<float*>(image->GetScalarPointer(i, j, k)) = 100.0f * (k - 30);
  vtkNew<vtkRPScalarVolumeNode> volume;
  volume->SetImageData(image);
  const double spacing[3] = {1, 1, 1}, origin[3] = {-20, -20, -30}, axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  volume->SetGeometry(spacing, origin, axes);
  volume->SetWindowLevel(6000, 0);  // S from −30 to +30 mm → black to white
  scene->AddNode(volume);
#ifdef ROBOPLAN_TEST_WITH_VIEWER
  rp::ViewController viewer(scene);  // a viewer on the same scene; the panel knows nothing of it
#endif
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  auto panel = std::make_unique<qRPHapticsPanel>(logic.GetPointer());
  panel->LogPathEdit()->setText("");
  auto pump = [&](double seconds) { Pump(app, *panel, seconds); };
  panel->FollowProxyCheckBox()->setChecked(true);  // before the proxy exists: applied when it does
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  panel->StylusSpinBox(0)->setValue(3);
  panel->StylusSpinBox(1)->setValue(-4);
  panel->StylusSpinBox(2)->setValue(10);  // in free space the proxy is the stylus tip
  pump(0.3);
  vtkRPNode* proxy = scene->GetFirstNodeByName(rp::HapticProxyName);
  ASSERT_NE(proxy, nullptr);
  const auto slices = vtkRPSliceNode::GetSliceNodes(scene);
  ASSERT_EQ(slices.size(), 3u);
  for (vtkRPSliceNode* slice : slices) EXPECT_EQ(slice->GetFollowNodeID(), proxy->GetID()) << slice->GetName();
  vtkRPSliceNode* red = vtkRPSliceNode::GetSliceNode(scene, "Red");
  EXPECT_NEAR(red->GetSliceOffset(), 10.0, 0.05);
  EXPECT_NEAR(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), 3.0, 0.05);
  EXPECT_NEAR(vtkRPSliceNode::GetSliceNode(scene, "Green")->GetSliceOffset(), -4.0, 0.05);
#ifdef ROBOPLAN_TEST_WITH_VIEWER
  rp::ScreenshotOptions options;
  options.Width = options.Height = 64;
  options.Layout = vtkRPLayoutNode::OneUpAxial;
  vtkNew<vtkImageData> first, second;
  std::string error;
  ASSERT_TRUE(rp::RenderViews(viewer, options, first, error)) << error;
  const int reslices = viewer.GetSliceLogic(rp::ViewKind::Axial)->GetNumberOfReslices();
  // The grey at a pixel off the crosshair: S = 10 → (1000 + 3000) / 6000 of white.
  const auto grey = [](vtkImageData* picture) { return static_cast<unsigned char*>(picture->GetScalarPointer(20, 44, 0))[0]; };
  EXPECT_NEAR(grey(first), 4000.0 / 6000.0 * 255, 3);
#endif
  // Into the slab: the proxy stays on the surface (S = 0), the stylus goes 2 mm below it.
  panel->StylusSpinBox(2)->setValue(-2);
  pump(0.3);
  EXPECT_NEAR(red->GetSliceOffset(), 0.0, 0.1);
#ifdef ROBOPLAN_TEST_WITH_VIEWER
  ASSERT_TRUE(rp::RenderViews(viewer, options, second, error)) << error;
  EXPECT_GT(viewer.GetSliceLogic(rp::ViewKind::Axial)->GetNumberOfReslices(), reslices);
  EXPECT_NEAR(grey(second), 3000.0 / 6000.0 * 255, 3);
#endif
  // Another module takes the slices over: the box unticks; unticking leaves them alone.
  vtkNew<vtkRPLinearTransformNode> stylus;
  scene->AddNode(stylus);
  vtkRPSliceNode::SetAllSlicesFollow(scene, stylus->GetID());
  pump(0.1);
  EXPECT_FALSE(panel->FollowProxyCheckBox()->isChecked());
  EXPECT_EQ(red->GetFollowNodeID(), stylus->GetID());
  // Ticking again takes them back; unticking stops following.
  panel->FollowProxyCheckBox()->setChecked(true);
  pump(0.1);
  EXPECT_EQ(red->GetFollowNodeID(), proxy->GetID());
  panel->FollowProxyCheckBox()->setChecked(false);
  EXPECT_EQ(red->GetFollowNodeID(), "");
  panel.reset();
}

// The Guidance group (issue 38): the plan's fixtures switched with the panel's boxes while the
// servo runs, against closed forms — axis guidance pulls the stylus held 1.5 mm off a straight
// trajectory with k·d towards the axis; the depth stop holds it at the target depth with k·2 mm
// when pushed 2 mm past; the surface constraint on the slab's model pulls the stylus 1 mm above
// it with k·1 mm onto it; the trajectory dragged 0.5 mm, the pull follows; every switch within the device's force step per tick; the status line
// says which fixture is engaged and how far; a fixture with nothing to act on is refused with
// its reason and its box unticked; the trajectory list follows the scene.
TEST(HapticsPanel, GuidanceGroupSwitchesThePlansFixturesWhileRunning) {
  int argc = 1;
  char name[] = "qRPHapticsPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  rptest::AddGuidanceScene(scene);
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  logic->SetRampSeconds(0.05);
  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  const std::string log = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/haptics-panel-guidance.csv";
  auto panel = std::make_unique<qRPHapticsPanel>(logic.GetPointer());
  panel->LogPathEdit()->setText(QString::fromStdString(log));
  qRPFixtureChoiceWidget* guidance = panel->GuidanceWidget();
  ASSERT_EQ(guidance->TrajectoryComboBox()->count(), 1);
  EXPECT_EQ(guidance->TrajectoryComboBox()->currentText(), "Plan");
  EXPECT_NE(guidance->SurfaceComboBox()->findText("model Slab"), -1);
  EXPECT_EQ(guidance->StatusText(), "no fixture acts (free hand)");
  auto pump = [&](double seconds) { Pump(app, *panel, seconds); };
  auto servoTime = [&] {
    rp::HapticState s;
    logic->GetSession()->Servo().ReadState(s);
    return s.Time;
  };
  auto force = [&] {  // a tick that ran on time, as the panel shows it
    rp::HapticState s;
    for (int i = 0; i < 100 && (!logic->GetSession()->Servo().ReadState(s) || s.StallLimited); ++i) QThread::msleep(1);
    return s.Force;
  };
  const double d = 1.5;
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  panel->StylusSpinBox(0)->setValue(d);
  EXPECT_DOUBLE_EQ(panel->StylusSpinBox(2)->value(), -50);  // above the slab, between entry and target
  pump(0.2);
  const rp::DeviceInfo device = logic->GetSession()->DeviceLimits();
  const double period = logic->GetSession()->StabilityPeriod();
  const double k = rp::RenderedFixtureStiffness(rp::DefaultFixtureTuning(rp::FixtureKind::AxisGuidance), device, period);

  const double axisOn = servoTime();
  guidance->AxisCheckBox()->click();
  pump(0.3);
  EXPECT_NEAR(force().x, -k * d, 1e-6);
  EXPECT_NEAR(panel->DisplayedForce(), k * d, 0.02);
  EXPECT_TRUE(guidance->StatusText().contains("axis guidance on 'Plan' (captures within 3.00 mm): ENGAGED, 1.50 mm off the axis, 0.90 N"))
      << guidance->StatusText().toStdString();

  // The trajectory dragged 0.5 mm towards the stylus while the guidance acts: the pull follows.
  auto* plan = vtkRPTrajectoryNode::SafeDownCast(scene->GetFirstNodeByName("Plan"));
  const double movedEntry[3] = {0.5, 0, rptest::EntryS}, movedTarget[3] = {0.5, 0, rptest::TargetS};
  plan->SetEntryAndTarget(movedEntry, movedTarget);
  pump(0.5);
  EXPECT_NEAR(force().x, -k * (d - 0.5), 1e-6);
  EXPECT_TRUE(guidance->StatusText().contains("ENGAGED, 1.00 mm off the axis")) << guidance->StatusText().toStdString();
  const double backEntry[3] = {0, 0, rptest::EntryS}, backTarget[3] = {0, 0, rptest::TargetS};
  plan->SetEntryAndTarget(backEntry, backTarget);
  pump(0.5);
  EXPECT_NEAR(force().x, -k * d, 1e-6);

  guidance->DepthCheckBox()->click();
  pump(0.15);
  const double pushed = servoTime();
  panel->StylusSpinBox(2)->setValue(rptest::TargetS - 2);
  pump(0.3);
  const double kDepth = rp::RenderedFixtureStiffness(rp::DefaultFixtureTuning(rp::FixtureKind::DepthStop), device, period);
  EXPECT_NEAR(force().z, kDepth * 2, 1e-5);
  EXPECT_TRUE(guidance->StatusText().contains("depth stop at the target of 'Plan': AT THE STOP")) << guidance->StatusText().toStdString();
  std::printf("Guidance group, axis + depth stop:\n%s\n", guidance->StatusText().toStdString().c_str());

  // The scene has no structure at risk: refused, named, the box unticked, the fixtures kept.
  guidance->ForbiddenCheckBox()->click();
  EXPECT_FALSE(guidance->ForbiddenCheckBox()->isChecked());
  EXPECT_TRUE(guidance->StatusText().startsWith("the plan has no structure at risk for a forbidden region"))
      << guidance->StatusText().toStdString();
  EXPECT_EQ(logic->GetPlanFixtures()->Count(), 2);

  // Both off, pushed past the target: back to no force.
  const double off = servoTime();
  guidance->AxisCheckBox()->click();
  guidance->DepthCheckBox()->click();
  pump(0.3);
  EXPECT_NEAR(rp::Norm(force()), 0, 1e-9);
  EXPECT_EQ(guidance->StatusText(), "no fixture acts (free hand)");
  const double free = servoTime();

  // The surface constraint on the slab's model (its top at S = −60), the stylus 1 mm above it.
  panel->StylusSpinBox(2)->setValue(-59);
  pump(0.1);
  guidance->SurfaceComboBox()->setCurrentIndex(guidance->SurfaceComboBox()->findText("model Slab"));
  guidance->SurfaceCheckBox()->click();
  pump(0.3);
  const double kSurface = rp::RenderedFixtureStiffness(rp::DefaultFixtureTuning(rp::FixtureKind::SurfaceConstraint), device, period);
  EXPECT_NEAR(force().z, -kSurface * 1.0, 1e-5);
  EXPECT_TRUE(guidance->StatusText().contains("surface constraint on 'Slab' (within 2.00 mm): HOLDING, 1.00 mm from the surface"))
      << guidance->StatusText().toStdString();

  // A trajectory added to the scene joins the list.
  vtkNew<vtkRPTrajectoryNode> second;
  second->SetName("Second");
  scene->AddNode(second);
  pump(0.4);
  EXPECT_EQ(guidance->TrajectoryComboBox()->count(), 2);
  // The fades' budget per tick is MaxForceRate × the period the servo assumes: the measured p99
  // once it grew past the nominal one (a loaded machine), never less.
  const double lastPeriod = logic->GetSession()->StabilityPeriod();
  panel->StartStopButton()->click();
  ASSERT_FALSE(panel->IsRunning());

  const std::vector<rptest::LogRow> rows = rptest::ReadSessionLog(log);
  const double limit = device.MaxForceRate * lastPeriod + 1e-4;
  EXPECT_LE(rptest::LargestStep(rows, axisOn, pushed - 0.01), limit);
  EXPECT_LE(rptest::LargestStep(rows, off, free), limit);
  panel.reset();
}
