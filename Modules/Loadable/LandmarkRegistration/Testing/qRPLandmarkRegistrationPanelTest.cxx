// The LandmarkRegistration panel on a scene built here: four image fiducials, a known
// TrackerToRAS, a stylus (StylusToTracker → StylusTipToStylus) whose tip is moved to each
// landmark's physical position. Collect point ×4 recovers TrackerToRAS exactly; the target gives
// a predicted TRE; "Apply to tools" puts the tip at the image landmark; a swapped pair is rejected.
#include <gtest/gtest.h>

#include <QApplication>
#include <QDir>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QPushButton>
#include <QTableWidget>
#include <QTest>

#include <cmath>
#include <string>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkTransform.h>

#include "qRPLandmarkRegistrationPanel.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLandmarkRegistrationLogic.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"

namespace {
const double Landmarks[4][3] = {{10, 20, 30}, {70, 25, 35}, {15, 85, 40}, {20, 30, 100}};
const double TipOffset[3] = {4, -3, 160};  // StylusTipToStylus (pivot-calibrated)

void Transform(vtkMatrix4x4* m, const double in[3], double out[3]) {
  const double p[4] = {in[0], in[1], in[2], 1};
  double q[4];
  m->MultiplyPoint(p, q);
  for (int k = 0; k < 3; ++k) out[k] = q[k];
}

/// Poses the stylus so that its tip is at `physical` (tracker coordinates), at some orientation.
void PlaceTip(vtkRPTrackedToolNode* stylusToTracker, const double physical[3], double angle) {
  vtkNew<vtkTransform> pose;
  pose->PostMultiply();
  pose->RotateWXYZ(angle, 0.3, 1, 0.2);
  vtkNew<vtkMatrix4x4> m;
  m->DeepCopy(pose->GetMatrix());
  double rotatedOffset[3];
  Transform(m, TipOffset, rotatedOffset);
  for (int k = 0; k < 3; ++k) m->SetElement(k, 3, physical[k] - rotatedOffset[k]);
  stylusToTracker->SetMatrixTransformToParent(m);
}
}  // namespace

TEST(LandmarkRegistrationPanel, CollectRegisterApplyAndRejectSwap) {
  int argc = 1;
  char name[] = "qRPLandmarkRegistrationPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);

  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPFiducialListNode> image;
  image->SetName("ImageLandmarks");
  for (int i = 0; i < 4; ++i) image->AddControlPoint(Landmarks[i], "L" + std::to_string(i + 1));
  scene->AddNode(image);
  vtkNew<vtkRPFiducialListNode> physical;
  physical->SetName("PhysicalLandmarks");
  scene->AddNode(physical);
  vtkNew<vtkRPTrackedToolNode> stylus;
  stylus->SetName("StylusToTracker");
  stylus->SetStatus(vtkRPTrackedToolNode::StatusOK);
  scene->AddNode(stylus);
  vtkNew<vtkRPLinearTransformNode> tip;
  tip->SetName("StylusTipToStylus");
  vtkNew<vtkMatrix4x4> tipMatrix;
  for (int k = 0; k < 3; ++k) tipMatrix->SetElement(k, 3, TipOffset[k]);
  tip->SetMatrixTransformToParent(tipMatrix);
  scene->AddNode(tip);
  ASSERT_TRUE(tip->SetAndObserveTransformNodeID(stylus->GetID()));

  // The truth: TrackerToRAS, and the landmarks' physical positions p = truth⁻¹ · q.
  vtkNew<vtkTransform> truthTransform;
  truthTransform->PostMultiply();
  truthTransform->RotateWXYZ(37, 1, 2, 3);
  truthTransform->Translate(-120, 45, 300);
  vtkNew<vtkMatrix4x4> truth, truthInverse;
  truth->DeepCopy(truthTransform->GetMatrix());
  vtkMatrix4x4::Invert(truth, truthInverse);

  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  qRPLandmarkRegistrationPanel panel(logic, scene);
  panel.show();
  ASSERT_TRUE(panel.SelectFromList("PhysicalLandmarks"));
  ASSERT_TRUE(panel.SelectToList("ImageLandmarks"));
  ASSERT_TRUE(panel.SelectToolTransform("StylusTipToStylus"));
  vtkRPLinearTransformNode* output = panel.CreateOutputTransform("TrackerToRAS");
  ASSERT_NE(output, nullptr);
  EXPECT_EQ(output->GetName(), "TrackerToRAS");
  EXPECT_EQ(logic->GetOutputTransform(), output);
  panel.ThresholdSpinBox()->setValue(1.0);
  panel.FLESpinBox()->setValue(0.25);
  EXPECT_DOUBLE_EQ(logic->GetFREThreshold(), 1.0);

  // A stylus out of the tracker's view is not collected.
  stylus->SetStatus(vtkRPTrackedToolNode::StatusMissing);
  EXPECT_FALSE(panel.CollectPoint());
  EXPECT_EQ(physical->GetNumberOfControlPoints(), 0);
  EXPECT_TRUE(panel.StatusText().contains("StylusToTracker is not tracked")) << panel.StatusText().toStdString();
  stylus->SetStatus(vtkRPTrackedToolNode::StatusOK);

  for (int i = 0; i < 4; ++i) {
    double p[3];
    Transform(truthInverse, Landmarks[i], p);
    PlaceTip(stylus, p, 20.0 * i + 5);
    QTest::mouseClick(panel.CollectButton(), Qt::LeftButton);
    ASSERT_EQ(physical->GetNumberOfControlPoints(), i + 1) << panel.StatusText().toStdString();
    EXPECT_EQ(physical->GetNthControlPoint(i).Label, "L" + std::to_string(i + 1));
    double collected[3];
    physical->GetNthControlPointPosition(i, collected);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(collected[k], p[k], 1e-9);
    if (i == 1) {
      EXPECT_TRUE(panel.StatusText().startsWith("collecting: 2 of 4")) << panel.StatusText().toStdString();
    }
  }

  // Recomputed automatically on the fourth point: the truth, FRE ≈ 0, accepted.
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "accepted");
  EXPECT_TRUE(panel.StatusText().startsWith("accepted")) << panel.StatusText().toStdString();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(output->GetMatrixTransformToParent()->GetElement(r, c), truth->GetElement(r, c), 1e-6);
  EXPECT_LT(std::stod(output->GetAttribute("Registration.FRE")), 1e-6);
  EXPECT_LT(logic->GetLastAssessment().Solution.FRE, 1e-6);
  QTableWidget* table = panel.PairTable();
  ASSERT_EQ(table->rowCount(), 4);
  for (int r = 0; r < 4; ++r) {
    EXPECT_EQ(table->item(r, qRPLandmarkRegistrationPanel::LabelColumn)->text(), QString("L%1").arg(r + 1));
    EXPECT_LT(table->item(r, qRPLandmarkRegistrationPanel::ResidualColumn)->text().toDouble(), 1e-3);
    EXPECT_EQ(table->item(r, qRPLandmarkRegistrationPanel::ResidualColumn)->background().color(), QColor(150, 220, 150));
  }

  // A target: predicted TRE from FLE and the fiducial geometry, stored on the output node.
  panel.TargetSpinBox(0)->setValue(40);
  panel.TargetSpinBox(1)->setValue(50);
  panel.TargetSpinBox(2)->setValue(60);
  panel.TargetCheckBox()->setChecked(true);
  EXPECT_EQ(output->GetAttribute("Registration.Target"), "40 50 60");
  const double tre = std::stod(output->GetAttribute("Registration.PredictedTRE"));
  const rp::TREPredictor predictor(
      rp::PointList{Eigen::Vector3d(Landmarks[0]), Eigen::Vector3d(Landmarks[1]), Eigen::Vector3d(Landmarks[2]),
                    Eigen::Vector3d(Landmarks[3])},
      0.25);
  EXPECT_NEAR(tre, predictor.PredictRMS(Eigen::Vector3d(40, 50, 60)), 1e-5);
  EXPECT_GT(tre, 0.25 / 2);  // FLE/sqrt(N) is the lower bound at the centroid
  EXPECT_TRUE(panel.TREText().contains("at the target")) << panel.TREText().toStdString();
  // A target list: the target follows its first point when it moves.
  vtkNew<vtkRPFiducialListNode> targetList;
  targetList->SetName("Target");
  const double entry[3] = {30, 40, 70};
  targetList->AddControlPoint(entry, "Entry");
  scene->AddNode(targetList);
  ASSERT_TRUE(panel.SelectTargetList("Target"));
  EXPECT_EQ(output->GetAttribute("Registration.Target"), "30 40 70");
  const double moved[3] = {35, 45, 75};
  targetList->SetNthControlPointPosition(0, moved);
  EXPECT_EQ(output->GetAttribute("Registration.Target"), "35 45 75");
  EXPECT_NEAR(std::stod(output->GetAttribute("Registration.PredictedTRE")),
              predictor.PredictRMS(Eigen::Vector3d(35, 45, 75)), 1e-5);
  ASSERT_TRUE(panel.SelectTargetList("(none)"));
  EXPECT_EQ(output->GetAttribute("Registration.Target"), "35 45 75");  // the spin boxes keep it

  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  panel.resize(700, 650);
  EXPECT_TRUE(panel.grab().save(QString(ROBOPLAN_TEST_OUTPUT_DIR) + "/panel-accepted.png"));

  // Apply to tools: the stylus and the physical points go under TrackerToRAS; the tip (still at
  // the last landmark) is now at the image landmark in world coordinates.
  QTest::mouseClick(panel.ApplyButton(), Qt::LeftButton);
  EXPECT_EQ(stylus->GetTransformNodeID(), output->GetID()) << panel.StatusText().toStdString();
  EXPECT_EQ(physical->GetTransformNodeID(), output->GetID());
  EXPECT_EQ(tip->GetTransformNodeID(), stylus->GetID());
  vtkNew<vtkMatrix4x4> tipToWorld;
  tip->GetMatrixTransformToWorld(tipToWorld);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(tipToWorld->GetElement(k, 3), Landmarks[3][k], 1e-6);
  double world[3];
  physical->GetNthControlPointPositionWorld(2, world);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(world[k], Landmarks[2][k], 1e-6);
  // Collecting again under the output still gives tracker coordinates (no feedback).
  QTest::mouseClick(panel.CollectButton(), Qt::LeftButton);
  ASSERT_EQ(physical->GetNumberOfControlPoints(), 5);
  double again[3], p3[3];
  physical->GetNthControlPointPosition(4, again);
  Transform(truthInverse, Landmarks[3], p3);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(again[k], p3[k], 1e-6);
  table->selectRow(4);
  QTest::mouseClick(panel.RemoveButton(), Qt::LeftButton);
  EXPECT_EQ(table->rowCount(), 4);
  EXPECT_TRUE(panel.StatusText().startsWith("accepted")) << panel.StatusText().toStdString();

  // A swapped pair: FRE far above the threshold, rejected (red), the matrix kept.
  double a[3], b[3];
  physical->GetNthControlPointPosition(0, a);
  physical->GetNthControlPointPosition(1, b);
  const int previous = physical->StartModify();
  physical->SetNthControlPointPosition(0, b);
  physical->SetNthControlPointPosition(1, a);
  physical->EndModify(previous);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "rejected");
  EXPECT_TRUE(panel.StatusText().startsWith("rejected")) << panel.StatusText().toStdString();
  EXPECT_GT(std::stod(output->GetAttribute("Registration.FRE")), 1.0);
  EXPECT_TRUE(panel.FREText().startsWith("FRE: ")) << panel.FREText().toStdString();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(output->GetMatrixTransformToParent()->GetElement(r, c), truth->GetElement(r, c), 1e-6);
  bool anyRed = false;
  for (int r = 0; r < 4; ++r)
    anyRed |= table->item(r, qRPLandmarkRegistrationPanel::ResidualColumn)->background().color() == QColor(240, 120, 120);
  EXPECT_TRUE(anyRed);
  EXPECT_TRUE(panel.grab().save(QString(ROBOPLAN_TEST_OUTPUT_DIR) + "/panel-rejected.png"));
  // "Apply to tools" refuses a rejected registration.
  EXPECT_FALSE(panel.ApplyToTools());

  // Raising the threshold above the FRE accepts (recomputed on the setting change).
  panel.ThresholdSpinBox()->setValue(99);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "accepted");

  // Removing the output and closing the scene empty the combos, the logic's inputs and the table.
  scene->RemoveNode(output);
  EXPECT_EQ(logic->GetOutputTransform(), nullptr);
  EXPECT_FALSE(panel.Register());
  scene->Clear();
  EXPECT_EQ(logic->GetFromFiducials(), nullptr);
  EXPECT_EQ(logic->GetToFiducials(), nullptr);
  EXPECT_EQ(table->rowCount(), 0);
  EXPECT_FALSE(panel.CollectPoint());
}

// Selecting a pair jumps the scene's slices to its image landmark (the views follow the scene;
// the panel has no view); a physical point without an image point is shown where the
// registration puts it; with the box unticked, selecting does not move the slices.
TEST(LandmarkRegistrationPanel, SelectingAPointJumpsTheSlicesToIt) {
  int argc = 1;
  char name[] = "qRPLandmarkRegistrationPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPFiducialListNode> image, physical;
  image->SetName("ImageLandmarks");
  physical->SetName("PhysicalLandmarks");
  for (int i = 0; i < 3; ++i) image->AddControlPoint(Landmarks[i], "L" + std::to_string(i + 1));
  for (int i = 0; i < 4; ++i) physical->AddControlPoint(Landmarks[i], "L" + std::to_string(i + 1));
  scene->AddNode(image);
  scene->AddNode(physical);
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;  // a registration shifting the physical points
  vtkNew<vtkMatrix4x4> shift;
  shift->SetElement(0, 3, 5);
  trackerToRAS->SetMatrixTransformToParent(shift);
  scene->AddNode(trackerToRAS);
  physical->SetAndObserveTransformNodeID(trackerToRAS->GetID());
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  qRPLandmarkRegistrationPanel panel(logic, scene);
  panel.show();
  ASSERT_TRUE(panel.SelectFromList("PhysicalLandmarks"));
  ASSERT_TRUE(panel.SelectToList("ImageLandmarks"));
  QTableWidget* table = panel.PairTable();
  ASSERT_EQ(table->rowCount(), 4);
  EXPECT_TRUE(panel.JumpSlicesCheckBox()->isChecked());

  table->selectRow(1);
  ASSERT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), Landmarks[1][2]);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), Landmarks[1][0]);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Green")->GetSliceOffset(), Landmarks[1][1]);
  // Row 4 has no image point: its physical point in RAS, through TrackerToRAS (+5 mm R).
  table->selectRow(3);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), Landmarks[3][0] + 5);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), Landmarks[3][2]);
  // Unticked: the slices stay.
  panel.JumpSlicesCheckBox()->setChecked(false);
  table->selectRow(0);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), Landmarks[3][2]);
}
