// The Drilling panel on a segmentation with a bone block and a protected layer under it: build
// the voxel bone, start the simulated device, drill with the burr moved by the spin boxes (the
// model node's mesh follows), undo the stroke (removed volume back to 0), drill down until the
// protected layer stops the burr (warning shown), reset, stop, save the tunnel picture.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <filesystem>
#include <memory>

#include <QApplication>
#include <QCheckBox>
#include <QProgressBar>
#include <QSet>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QThread>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "qRPDrillingPanel.h"
#include "qRPFixtureChoiceWidget.h"
#include "rpDrillServo.h"
#include "rpTestTime.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

namespace {
// Labels on a 1 mm grid centred at the origin: trabecular bone for |R|,|A| <= 10, −2 <= S <= 12;
// a protected layer under it (−6 <= S < −2); `atRisk`: that layer is a structure at risk of the
// plan too (protected, 1 mm margin); `top`: the bone's top voxels' S.
void AddSegmentation(vtkRPScene* scene, bool atRisk = false, int top = 12) {
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(36, 36, 36 + top - 12);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  for (int k = 0; k < 36 + top - 12; ++k)
    for (int j = 0; j < 36; ++j)
      for (int i = 0; i < 36; ++i) {
        const double r = i - 18, a = j - 18, s = k - 16;
        const bool box = std::fabs(r) <= 10 && std::fabs(a) <= 10;
        static_cast<unsigned char*>(labels->GetScalarPointer(i, j, k))[0] =
            box && s >= -2 && s <= top ? 1 : (box && s >= -6 && s < -2 ? 2 : 0);
      }
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName("Knee");
  segmentation->SetImageData(labels);
  const double spacing[3] = {1, 1, 1}, origin[3] = {-18, -18, -16}, directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  segmentation->SetGeometry(spacing, origin, directions);
  vtkRPSegmentationNode::Segment bone;
  bone.ID = "tibia";
  bone.Name = "Tibia";
  bone.LabelValue = 1;
  bone.TissueClass = "trabecular bone";
  segmentation->SetSegment(bone);
  vtkRPSegmentationNode::Segment guarded;
  guarded.ID = "posterior";
  guarded.Name = "Posterior cortex";
  guarded.LabelValue = 2;
  guarded.TissueClass = "bone";
  guarded.Protection = {atRisk, atRisk ? 1.0 : 0.0};
  segmentation->SetSegment(guarded);
  scene->AddNode(segmentation);
}
}  // namespace

TEST(DrillingPanel, BuildDrillUndoProtectedResetPicture) {
  int argc = 1;
  char name[] = "qRPDrillingPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  AddSegmentation(scene);
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(scene);
  const std::filesystem::path out = std::filesystem::path(ROBOPLAN_TEST_OUTPUT_DIR);
  std::filesystem::create_directories(out);

  auto panel = std::make_unique<qRPDrillingPanel>(logic.GetPointer());
  panel->show();
  ASSERT_EQ(panel->SegmentationComboBox()->count(), 1);
  ASSERT_EQ(panel->BoneList()->count(), 2);
  panel->BoneList()->item(0)->setCheckState(Qt::Checked);       // tibia
  panel->ProtectedList()->item(1)->setCheckState(Qt::Checked);  // posterior cortex
  panel->RecordPathEdit()->setText(QString::fromStdString((out / "panel-drill.txt").string()));
  panel->BuildButton()->click();
  ASSERT_TRUE(logic->HasBone()) << panel->BoneText().toStdString();
  EXPECT_TRUE(panel->BoneText().contains("blocks")) << panel->BoneText().toStdString();
  auto* model = vtkRPModelNode::SafeDownCast(scene->GetNodeByID(logic->GetDrilledModelID()));
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->GetName(), "Tibia (drilled)");
  const vtkIdType pointsBefore = model->GetPolyData()->GetNumberOfPoints();
  ASSERT_GT(pointsBefore, 100);

  auto pump = [&](double seconds, const std::function<bool()>& until = nullptr) {
    const auto end =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(rptest::WaitSeconds(seconds));
    while (std::chrono::steady_clock::now() < end) {
      app.processEvents();
      panel->Update();
      if (until && until()) return true;
      QThread::msleep(10);
    }
    return false;
  };
  panel->BurrSpinBox(0)->setValue(0.2);
  panel->BurrSpinBox(1)->setValue(-0.3);
  panel->BurrSpinBox(2)->setValue(20);  // above the bone (top at S = 12.5)
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  pump(0.2);
  // A stroke: burr on, pushed 4 mm into the top face.
  panel->BurrButton()->setChecked(true);
  panel->BurrSpinBox(2)->setValue(12.5 + 2.0 - 4.0);
  EXPECT_TRUE(pump(6.0, [&] { return panel->RemovedTotal() > 15.0; })) << panel->RemovedText().toStdString();
  // The display thread's re-contoured mesh reaches the model node.
  EXPECT_TRUE(pump(3.0, [&] { return model->GetPolyData()->GetNumberOfPoints() != pointsBefore; }));
  EXPECT_TRUE(panel->RemovedText().contains("trabecular bone")) << panel->RemovedText().toStdString();
  // Out again, burr off, undo: nothing removed any more.
  panel->BurrSpinBox(2)->setValue(20);
  pump(0.2);
  panel->BurrButton()->setChecked(false);
  pump(0.1);
  panel->UndoButton()->click();
  EXPECT_TRUE(pump(2.0, [&] { return panel->RemovedTotal() == 0.0; })) << panel->RemovedText().toStdString();

  // Drill straight down towards the protected layer: the burr is stopped above it, in red.
  panel->BurrButton()->setChecked(true);
  panel->BurrSpinBox(2)->setValue(-12);
  EXPECT_TRUE(pump(12.0, [&] { return panel->StatusText().startsWith("STOPPED"); })) << panel->StatusText().toStdString();
  EXPECT_TRUE(panel->ProtectedWarning());
  rp::DrillState state;
  ASSERT_TRUE(logic->ReadState(state));
  EXPECT_GT(state.RemovedTotalMm3, 100.0);
  EXPECT_LT(state.ClosestApproach, 0.5);
  EXPECT_GT(state.Proxy.z, -2.5 + 2.0 - 0.5);  // the burr's sphere stayed out of the layer
  std::printf("stopped above the protected layer: %s; %s\n", panel->ProtectedText().toStdString().c_str(),
              panel->RemovedText().toStdString().c_str());

  // A picture of the tunnel drilled, then reset the bone and stop.
  panel->BurrButton()->setChecked(false);
  panel->BurrSpinBox(2)->setValue(20);
  pump(0.3);
  const std::string picture = (out / "panel-tunnel.png").string();
  EXPECT_TRUE(panel->SavePicture(QString::fromStdString(picture))) << panel->StatusText().toStdString();
  EXPECT_TRUE(std::filesystem::exists(picture));
  panel->ResetButton()->click();
  EXPECT_TRUE(pump(2.0, [&] { return panel->RemovedTotal() == 0.0; })) << panel->RemovedText().toStdString();
  panel->StartStopButton()->click();
  EXPECT_FALSE(panel->IsRunning());
  EXPECT_TRUE(std::filesystem::file_size(out / "panel-drill.txt") > 1000);
  panel.reset();  // closing the panel stops everything
  EXPECT_FALSE(logic->IsRunning());
}

// The Guidance group and "Execute plan with simulated hand" (issue 38) on a taller block, a
// 25 mm tunnel planned straight down its middle, the protected layer a structure at risk: axis
// guidance switched on while the servo runs engages on the burr held 1 mm off the axis (the
// status line says so); the plan executed by a hand with 0.2 mm tremor and 1 mm/s drift scores
// within the targets with axis guidance and the depth stop (entry and tip ≤ 0.5 mm, angle
// ≤ 1°, no overshoot past 0.1 mm) and with the forbidden region too (never entered), while the
// same hand free overshoots the target; the window is repainted with progress while it drills.
TEST(DrillingPanel, GuidanceSwitchesAndExecutesThePlanWithTheSimulatedHand) {
  int argc = 1;
  char name[] = "qRPDrillingPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  AddSegmentation(scene, true, 27);  // bone top at S = 27.5
  vtkNew<vtkRPTrajectoryNode> tunnel;
  tunnel->SetName("Tunnel");
  const double entry[3] = {0, 0, 27.5}, target[3] = {0, 0, 2.5};
  tunnel->SetEntryAndTarget(entry, target);
  tunnel->SetToolDiameterMm(4);
  scene->AddNode(tunnel);
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(scene);
  auto panel = std::make_unique<qRPDrillingPanel>(logic.GetPointer());
  panel->RecordPathEdit()->setText("");
  panel->BoneList()->item(0)->setCheckState(Qt::Checked);  // tibia
  qRPFixtureChoiceWidget* guidance = panel->GuidanceWidget();
  ASSERT_EQ(guidance->TrajectoryComboBox()->currentText(), "Tunnel");

  // Axis guidance switched on while drilling runs, the burr 1 mm off the axis above the bone.
  panel->BuildButton()->click();
  ASSERT_TRUE(logic->HasBone()) << panel->BoneText().toStdString();
  panel->BurrSpinBox(0)->setValue(1.0);
  panel->BurrSpinBox(1)->setValue(0.0);
  panel->BurrSpinBox(2)->setValue(31);
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  guidance->AxisCheckBox()->click();
  rp::DrillState state;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(rptest::WaitSeconds(2.0));
  while (std::chrono::steady_clock::now() < end &&
         !(logic->ReadState(state) && state.Fixtures.Count == 1 && state.Fixtures.Fixtures[0].Weight >= 1)) {
    app.processEvents();
    panel->Update();
    QThread::msleep(10);
  }
  panel->Update();
  ASSERT_EQ(state.Fixtures.Count, 1);
  EXPECT_TRUE(state.Fixtures.Fixtures[0].Engaged);
  EXPECT_NEAR(state.Fixtures.Fixtures[0].Distance, 1.0, 1e-9);
  EXPECT_TRUE(guidance->StatusText().startsWith("axis guidance on 'Tunnel' (captures within 3.00 mm): ENGAGED, 1.00 mm off the axis"))
      << guidance->StatusText().toStdString();
  panel->StartStopButton()->click();
  ASSERT_FALSE(panel->IsRunning());

  // The plan executed three ways under one hand (each on a freshly built bone).
  panel->TremorSpinBox()->setValue(0.2);
  panel->DriftSpinBox()->setValue(1.0);
  panel->HandSpeedSpinBox()->setValue(2.5);
  panel->SeedSpinBox()->setValue(3);
  ASSERT_TRUE(panel->FreshBoneCheckBox()->isChecked());
  QSet<int> shown;  // progress the window showed while drilling
  QObject::connect(panel->ExecuteProgressBar(), &QProgressBar::valueChanged, [&](int v) { shown.insert(v); });
  auto execute = [&](bool axis, bool depth, bool forbidden) -> const rp::GuidedDrillResult& {
    if (guidance->AxisCheckBox()->isChecked() != axis) guidance->AxisCheckBox()->click();
    if (guidance->DepthCheckBox()->isChecked() != depth) guidance->DepthCheckBox()->click();
    if (guidance->ForbiddenCheckBox()->isChecked() != forbidden) guidance->ForbiddenCheckBox()->click();
    EXPECT_EQ(guidance->ForbiddenCheckBox()->isChecked(), forbidden) << guidance->StatusText().toStdString();
    panel->ExecuteButton()->click();
    std::printf("%s\n", panel->ExecutionText().toStdString().c_str());
    EXPECT_TRUE(panel->ExecutionText().contains("entry")) << panel->ExecutionText().toStdString();
    return panel->LastExecution();
  };
  const rp::GuidedDrillResult free = execute(false, false, false);
  EXPECT_TRUE(panel->ExecutionText().startsWith("'Tunnel', free hand: entry")) << panel->ExecutionText().toStdString();
  EXPECT_EQ(free.Fixtures, nullptr);
  EXPECT_TRUE(panel->isEnabled());
  EXPECT_GE(shown.size(), 5);  // the bar moved during the run, not only at its ends
  EXPECT_TRUE(shown.contains(1000));
  EXPECT_GT(free.Score.DepthErrorMm, 1.0);  // the hand's push carries the free burr past the target
  const rp::GuidedDrillResult guided = execute(true, true, false);
  ASSERT_NE(guided.Fixtures, nullptr);
  EXPECT_EQ(guided.Fixtures->Count(), 2);
  EXPECT_TRUE(panel->ExecutionText().contains("axis guidance on 'Tunnel'") &&
              panel->ExecutionText().contains("depth stop at the target of 'Tunnel'"))
      << panel->ExecutionText().toStdString();
  EXPECT_LE(guided.Score.EntryOffsetMm, 0.5);
  EXPECT_LE(guided.Score.TipOffsetMm, 0.5);
  EXPECT_LE(guided.Score.AngleDeg, 1.0);
  EXPECT_LE(guided.Score.DepthErrorMm, 0.1);
  EXPECT_GE(guided.Score.DepthErrorMm, -0.5);  // and it got there
  EXPECT_FALSE(guided.EnteredForbidden);
  EXPECT_TRUE(panel->ExecutionText().contains(QString("depth error %1 mm").arg(guided.Score.DepthErrorMm, 0, 'f', 2)));
  const rp::GuidedDrillResult guarded = execute(true, true, true);
  ASSERT_NE(guarded.Fixtures, nullptr);
  EXPECT_EQ(guarded.Fixtures->Count(), 3);
  EXPECT_TRUE(panel->ExecutionText().contains("forbidden region 'Posterior cortex'")) << panel->ExecutionText().toStdString();
  EXPECT_FALSE(guarded.EnteredForbidden);
  ASSERT_EQ(guarded.Score.Clearance.size(), 1u);
  EXPECT_GE(guarded.Score.Clearance[0].ClosestMm, 1.0 - 1e-6);  // outside the 1 mm margin
  EXPECT_LE(guarded.Score.TipOffsetMm, 0.5);
  EXPECT_LE(guarded.Score.AngleDeg, 1.0);
  // The Guidance group's fixtures are the logic's again for the next session.
  ASSERT_NE(logic->GetPlanFixtures(), nullptr);
  EXPECT_EQ(logic->GetPlanFixtures()->Count(), 3);

  // A plan without the trajectory chosen: the reason, nothing drilled.
  scene->RemoveNode(tunnel);
  guidance->RefreshNodes();
  EXPECT_EQ(guidance->TrajectoryComboBox()->count(), 0);
  panel->ExecuteButton()->click();
  EXPECT_TRUE(panel->ExecutionText().startsWith("the scene has no complete trajectory")) << panel->ExecutionText().toStdString();
  std::printf("without a trajectory: %s\n", panel->ExecutionText().toStdString().c_str());
  panel.reset();
}
