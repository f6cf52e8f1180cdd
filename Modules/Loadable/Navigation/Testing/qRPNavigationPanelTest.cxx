// The Navigation panel on an analytic scene: a sphere of radius 20 mm at the origin and a tool
// transform on its +S axis. Known answers: at 35 mm from the centre the tip is 15.0 mm from the
// surface (green, over the 3 mm warning); at 21 mm it is 1.0 mm (red). The sphere's poles are
// mesh vertices, so on the S axis the tessellated surface is exactly at radius 20. The tool read
// out against a planned trajectory (closed form).
#include <gtest/gtest.h>

#include <chrono>

#include <QApplication>
#include <QComboBox>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QSpinBox>
#include <QListWidget>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>

#include <vtkImageData.h>

#include "qRPNavigationPanel.h"
#include "rpTargetView.h"
#include "rpTestOutput.h"
#include "vtkRPScalarVolumeNode.h"
#include "qRPSliceFollowCheckBox.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrajectoryNode.h"

TEST(NavigationPanel, DistanceToSphereGreenThenRedUnderWarning) {
  int argc = 1;
  char name[] = "qRPNavigationPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(20);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(64);
  sphere->Update();
  vtkNew<vtkRPModelNode> bone;
  bone->SetName("Femur");
  bone->SetPolyData(sphere->GetOutput());
  scene->AddNode(bone);
  vtkNew<vtkRPModelNode> other;  // far away, not ticked: must not be measured to
  other->SetName("Far sphere");
  vtkNew<vtkSphereSource> far;
  far->SetCenter(0, 0, 40);
  far->SetRadius(1);
  far->Update();
  other->SetPolyData(far->GetOutput());
  scene->AddNode(other);
  vtkNew<vtkRPLinearTransformNode> unrelated;
  unrelated->SetName("TrackerToRAS");
  scene->AddNode(unrelated);
  vtkNew<vtkRPLinearTransformNode> tool;
  tool->SetName("StylusTipToStylus");
  scene->AddNode(tool);
  auto moveTool = [&](double s) {
    vtkNew<vtkMatrix4x4> m;
    m->SetElement(2, 3, s);
    tool->SetMatrixTransformToParent(m);
  };
  moveTool(35);

  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  qRPNavigationPanel panel(logic);
  panel.show();
  app.processEvents();
  // The stylus tip is chosen by default; two models listed, none ticked yet.
  EXPECT_EQ(panel.ToolComboBox()->currentText(), "StylusTipToStylus");
  ASSERT_EQ(panel.ModelList()->count(), 2);
  EXPECT_EQ(panel.DistanceText(), "-");
  panel.WarningSpinBox()->setValue(3.0);
  panel.ModelList()->item(0)->setCheckState(Qt::Checked);  // Femur
  app.processEvents();
  EXPECT_EQ(panel.DistanceText(), "15.0 mm");
  EXPECT_FALSE(panel.IsWarningShown());
  EXPECT_EQ(panel.ClosestModelText(), "closest: Femur");
  EXPECT_EQ(tool->GetAttribute("Navigation.Warning"), "0");
  EXPECT_NEAR(std::stod(tool->GetAttribute("Navigation.DistanceMM")), 15.0, 1e-9);

  moveTool(21);
  panel.Update();  // what the panel's 30 Hz timer does
  EXPECT_EQ(panel.DistanceText(), "1.0 mm");
  EXPECT_TRUE(panel.IsWarningShown());
  EXPECT_EQ(tool->GetAttribute("Navigation.Warning"), "1");

  // A smaller warning distance takes the warning away again.
  panel.WarningSpinBox()->setValue(0.5);
  EXPECT_FALSE(panel.IsWarningShown());
  EXPECT_EQ(panel.DistanceText(), "1.0 mm");

  // A model added to the scene shows up in the list on the next timer tick, unticked.
  vtkNew<vtkRPModelNode> added;
  added->SetName("Tibia");
  scene->AddNode(added);
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(2000);
  while (std::chrono::steady_clock::now() < end && panel.ModelList()->count() < 3) app.processEvents(QEventLoop::AllEvents, 20);
  ASSERT_EQ(panel.ModelList()->count(), 3);
  EXPECT_EQ(panel.ModelList()->item(2)->text(), "Tibia");
  EXPECT_EQ(panel.ModelList()->item(0)->checkState(), Qt::Checked);
  EXPECT_EQ(panel.ModelList()->item(2)->checkState(), Qt::Unchecked);
  EXPECT_EQ(panel.DistanceText(), "1.0 mm");

  // A planned trajectory (issue 38) added and chosen: the tool, on the S axis 21 mm up and pointing
  // down it, is read out against a plan from (3, 4, 30) down to (3, 4, 0): 5 mm off at the entry
  // and laterally, 0°, 21 mm from the target.
  EXPECT_EQ(panel.ReadoutText(), "-");
  vtkNew<vtkRPTrajectoryNode> plan;
  plan->SetName("Tunnel");
  const double entry[3] = {3, 4, 30}, target[3] = {3, 4, 0};
  plan->SetEntryAndTarget(entry, target);
  scene->AddNode(plan);
  const auto listed = std::chrono::steady_clock::now() + std::chrono::milliseconds(2000);
  while (std::chrono::steady_clock::now() < listed && panel.TrajectoryComboBox()->count() < 2)
    app.processEvents(QEventLoop::AllEvents, 20);
  ASSERT_EQ(panel.TrajectoryComboBox()->count(), 2);
  panel.TrajectoryComboBox()->setCurrentIndex(1);
  EXPECT_EQ(panel.ReadoutText(), QString::fromUtf8("entry 5.0 mm · angle 0.0° · depth to target 21.0 mm · lateral 5.0 mm"));
  EXPECT_EQ(logic->GetTrajectoryNodeID(), plan->GetID());

  // The femur flagged a structure at risk with a 3 mm margin: the tip 1 mm above its pole, the
  // plan's tool (2 mm across) touches it: 0.0 mm, red.
  EXPECT_FALSE(panel.IsStructureWarningShown());
  bone->SetProtection({true, 3.0});
  panel.Update();
  EXPECT_EQ(panel.StructureText(), "closest structure at risk: Femur 0.0 mm (within its margin)");
  EXPECT_TRUE(panel.IsStructureWarningShown());
}

// The target view (issue 38) with a known pose: a plan straight down −S from the origin, the tool
// tip 2 mm to the right of it (R) at 10 mm deep, pointing down the plan. In the target view (7 mm
// from the centre to the edge of a 240-pixel pane) the tip is drawn 2 mm right of the centre, in the
// view across the plan (60 mm field) too; the tilted tool's axis crosses the entry plane where the
// read-out's entry error says. Writes the picture (target_view.png) to look at.
TEST(NavigationPanel, TheTargetViewDrawsTheTipAtItsOffsetFromThePlan) {
  int argc = 1;
  char name[] = "qRPNavigationPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrajectoryNode> plan;
  plan->SetName("Tunnel");
  const double entry[3] = {0, 0, 0}, target[3] = {0, 0, -40};
  plan->SetEntryAndTarget(entry, target);
  scene->AddNode(plan);
  // A CT-like volume: a 30 mm ball of 1000 in 0, 1 mm voxels around the plan.
  vtkNew<vtkImageData> image;
  image->SetDimensions(81, 81, 81);
  image->AllocateScalars(VTK_SHORT, 1);
  for (int k = 0; k < 81; ++k)
    for (int j = 0; j < 81; ++j)
      for (int i = 0; i < 81; ++i)
        *static_cast<short*>(image->GetScalarPointer(i, j, k)) =
            (i - 40) * (i - 40) + (j - 40) * (j - 40) + (k - 40) * (k - 40) < 900 ? 1000 : 0;
  vtkNew<vtkRPScalarVolumeNode> ct;
  ct->SetName("CT");
  ct->SetImageData(image);
  vtkNew<vtkMatrix4x4> ijkToRAS;
  for (int a = 0; a < 3; ++a) ijkToRAS->SetElement(a, 3, a == 2 ? -60 : -40);
  ct->SetIJKToRASMatrix(ijkToRAS);
  scene->AddNode(ct);
  vtkNew<vtkRPLinearTransformNode> tool;
  tool->SetName("StylusTipToStylus");
  scene->AddNode(tool);
  vtkNew<vtkMatrix4x4> pose;
  pose->SetElement(0, 3, 2);
  pose->SetElement(2, 3, -10);
  tool->SetMatrixTransformToParent(pose);

  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  qRPNavigationPanel panel(logic);
  panel.show();
  app.processEvents();
  ASSERT_EQ(panel.VolumeComboBox()->currentText(), "CT");
  panel.TrajectoryComboBox()->setCurrentIndex(1);
  panel.Update();
  const rp::TargetViewPicture* view = panel.TargetView();
  ASSERT_TRUE(view && view->GetImage()) << panel.ReadoutText().toStdString();
  vtkImageData* picture = view->GetImage();
  int dims[3];
  picture->GetDimensions(dims);
  const int pane = view->GetOptions().PaneSize;
  ASSERT_EQ(dims[0], 3 * pane);
  ASSERT_EQ(dims[1], pane);
  EXPECT_EQ(panel.TargetViewImage().width(), 3 * pane);
  // The centroid of the tip's colour in a pane (pixel centres; rows from the bottom).
  auto tipCentroid = [&](int which, double c[2]) {
    double sum[2] = {0, 0};
    int n = 0;
    for (int j = 0; j < dims[1]; ++j)
      for (int i = which * pane; i < (which + 1) * pane; ++i) {
        const auto* rgb = static_cast<const unsigned char*>(picture->GetScalarPointer(i, j, 0));
        if (rgb[1] > 200 && rgb[0] < 80 && rgb[2] < 80) {
          sum[0] += i - which * pane + 0.5;
          sum[1] += j + 0.5;
          ++n;
        }
      }
    c[0] = n ? sum[0] / n : -1;
    c[1] = n ? sum[1] / n : -1;
    return n;
  };
  const std::string png = (rptest::TestDir("qRPNavigationPanelTest") / "target_view.png").string();
  std::string error;
  EXPECT_TRUE(view->WritePNG(png, error)) << error;
  double tip[2], expected[2];
  ASSERT_GT(tipCentroid(0, tip), 10);
  const double offset[2] = {2, 0};
  view->TargetViewToPixel(offset, expected);
  const double perMm = pane / (2 * view->GetOptions().HalfWidthMm);
  EXPECT_NEAR(tip[0], expected[0], 1.0);
  EXPECT_NEAR(tip[1], expected[1], 1.0);
  EXPECT_NEAR((tip[0] - 0.5 * pane) / perMm, 2.0, 1.0 / perMm);  // 2 mm right of the target
  EXPECT_NEAR(tip[1], 0.5 * pane, 1.0);
  // Across the plan at the tip: the same 2 mm to the right of the axis.
  ASSERT_GT(tipCentroid(2, tip), 10);
  const double slicePerMm = pane / view->GetOptions().SliceFieldMm;
  EXPECT_NEAR((tip[0] - 0.5 * pane) / slicePerMm, 2.0, 1.0 / slicePerMm);
  EXPECT_NEAR(tip[1], 0.5 * pane, 1.0);
  // Along the plan (entry up): the tip 2 mm right, at the pane's middle (the slice is at its depth).
  ASSERT_GT(tipCentroid(1, tip), 10);
  EXPECT_NEAR((tip[0] - 0.5 * pane) / slicePerMm, 2.0, 1.0 / slicePerMm);

  // Tilted 10° about A (the tip's −z leans towards +R going down): its axis crosses the entry plane
  // 10·tan 10° to the left of the tip, the geometry the view draws the yellow diamond at.
  const double t = 10 * M_PI / 180;
  pose->SetElement(0, 0, std::cos(t));
  pose->SetElement(0, 2, -std::sin(t));
  pose->SetElement(2, 0, std::sin(t));
  pose->SetElement(2, 2, std::cos(t));
  tool->SetMatrixTransformToParent(pose);
  const rp::TargetViewGeometry g = rp::ComputeTargetViewGeometry(logic->GetLastReadout(), 40);
  ASSERT_TRUE(g.Crosses);
  EXPECT_NEAR(g.EntryCrossing[0], 2 - 10 * std::tan(t), 1e-9);
  EXPECT_NEAR(std::hypot(g.EntryCrossing[0], g.EntryCrossing[1]), logic->GetLastReadout().EntryErrorMm, 1e-9);
  EXPECT_NEAR(g.TargetCrossing[0], 2 + 30 * std::tan(t), 1e-9);
  panel.Update();
  EXPECT_TRUE(view->WritePNG((rptest::TestDir("qRPNavigationPanelTest-tilted") / "target_view.png").string(), error)) << error;

  // "Stream read-outs over OpenIGTLink" on a port another server holds: the reason is shown and the
  // box unticks; once the port is free, it streams there.
  vtkNew<vtkRPNavigationLogic> other;
  ASSERT_TRUE(other->StartReadoutServer(0, error)) << error;
  const int port = other->GetReadoutServerPort();
  panel.StreamPortSpinBox()->setValue(port);
  panel.StreamCheckBox()->setChecked(true);
  EXPECT_FALSE(panel.StreamCheckBox()->isChecked());
  EXPECT_TRUE(panel.StreamText().contains("cannot listen on 127.0.0.1:" + QString::number(port))) << panel.StreamText().toStdString();
  other->StopReadoutServer();
  panel.StreamCheckBox()->setChecked(true);
  panel.Update();
  EXPECT_EQ(logic->GetReadoutServerPort(), port);
  EXPECT_EQ(panel.StreamText(), QString("streaming on 127.0.0.1:%1, 0 client(s)").arg(port));
  panel.StreamCheckBox()->setChecked(false);
  EXPECT_EQ(logic->GetReadoutServerPort(), 0);
}

// "Slices follow the tool": the scene's slice nodes follow the tracked stylus tip (StylusTip
// under StylusToTracker under TrackerToRAS); moving the tracker pose or the registration moves
// the slices; choosing another tool moves them over to it.
TEST(NavigationPanel, SlicesFollowTheTrackedStylus) {
  int argc = 1;
  char name[] = "qRPNavigationPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> trackerToRAS, tipToStylus, proxy;
  trackerToRAS->SetName("TrackerToRAS");
  tipToStylus->SetName("StylusTipToStylus");
  proxy->SetName("HapticProxy");
  vtkNew<vtkRPTrackedToolNode> stylus;
  stylus->SetName("StylusToTracker");
  for (vtkRPNode* node : std::initializer_list<vtkRPNode*>{trackerToRAS, stylus, tipToStylus, proxy}) scene->AddNode(node);
  stylus->SetAndObserveTransformNodeID(trackerToRAS->GetID());
  tipToStylus->SetAndObserveTransformNodeID(stylus->GetID());
  vtkNew<vtkMatrix4x4> tip, pose, registration;
  tip->SetElement(2, 3, -100);  // the tip 100 mm down the shaft
  tipToStylus->SetMatrixTransformToParent(tip);
  pose->SetElement(0, 3, 10);
  pose->SetElement(1, 3, 20);
  pose->SetElement(2, 3, 130);
  stylus->SetMatrixTransformToParent(pose);  // tip at (10, 20, 30) in RAS

  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  qRPNavigationPanel panel(logic);
  panel.show();
  app.processEvents();
  ASSERT_EQ(panel.ToolComboBox()->currentText(), "StylusTipToStylus");
  panel.FollowToolCheckBox()->setChecked(true);
  const auto slices = vtkRPSliceNode::GetSliceNodes(scene);
  ASSERT_EQ(slices.size(), 3u);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), 30);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), 10);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Green")->GetSliceOffset(), 20);
  // The tracker reports a new pose: the slices move with the tip.
  pose->SetElement(2, 3, 145);
  stylus->SetMatrixTransformToParent(pose);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), 45);
  // The registration changes (TrackerToRAS): the tip moves in RAS, so do the slices.
  registration->SetElement(0, 3, -5);
  trackerToRAS->SetMatrixTransformToParent(registration);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), 5);
  // Another tool chosen in the panel: the slices follow it instead.
  panel.ToolComboBox()->setCurrentIndex(panel.ToolComboBox()->findText("HapticProxy"));
  app.processEvents();
  for (vtkRPSliceNode* slice : slices) EXPECT_EQ(slice->GetFollowNodeID(), proxy->GetID());
  // Unticked: the slices stay where they are.
  panel.FollowToolCheckBox()->setChecked(false);
  for (vtkRPSliceNode* slice : slices) EXPECT_EQ(slice->GetFollowNodeID(), "");
}
