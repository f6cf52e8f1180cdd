// The Planning panel on a CT with a block of bone and a vessel beside it: a new trajectory placed
// and dragged (as the views do, through its control points) has its figures follow at display
// rate; flagging the vessel at risk in the panel stores it on the model and adds its clearance,
// red under the margin; a proposal from an entry patch makes the risk map model.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QTableWidget>
#include <QThread>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkSphereSource.h>
#include <vtkTriangleFilter.h>

#include "qRPPlanningPanel.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"

namespace {

int argc = 1;
char name[] = "qRPPlanningPanelTest";
char* argv[] = {name, nullptr};

// 1 mm CT over [-30, 30]^3: bone (1000 HU) in |R|, |A| <= 10, |S| <= 20.
void AddCT(vtkRPScene* scene) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(61, 61, 61);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < 61; ++k)
    for (int j = 0; j < 61; ++j)
      for (int i = 0; i < 61; ++i) *v++ = std::abs(i - 30) <= 10 && std::abs(j - 30) <= 10 && std::abs(k - 30) <= 20 ? 1000 : -1000;
  vtkNew<vtkRPScalarVolumeNode> ct;
  ct->SetName("CT");
  ct->SetImageData(image);
  const double spacing[3] = {1, 1, 1}, origin[3] = {-30, -30, -30}, directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ct->SetGeometry(spacing, origin, directions);
  scene->AddNode(ct);
}

vtkRPModelNode* AddModel(vtkRPScene* scene, const char* name, vtkPolyData* mesh) {
  vtkNew<vtkRPModelNode> model;
  model->SetName(name);
  model->SetPolyData(mesh);
  return vtkRPModelNode::SafeDownCast(scene->AddNode(model));
}

void Wait(int ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < end) {
    QApplication::processEvents();
    QThread::msleep(5);
  }
}

}  // namespace

TEST(PlanningPanel, FiguresFollowADraggedTrajectoryAndTheStructuresAtRisk) {
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  AddCT(scene);
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(16, 0, 0);
  sphere->SetRadius(3);
  sphere->SetThetaResolution(48);
  sphere->SetPhiResolution(24);
  sphere->Update();
  vtkRPModelNode* vessel = AddModel(scene, "Vessel", sphere->GetOutput());
  vtkNew<vtkPlaneSource> patch;  // the entry region: a patch below the bone
  patch->SetOrigin(-8, -8, -26);
  patch->SetPoint1(8, -8, -26);
  patch->SetPoint2(-8, 8, -26);
  patch->SetResolution(8, 8);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(patch->GetOutputPort());
  triangles->Update();
  AddModel(scene, "Entry patch", triangles->GetOutput());
  vtkNew<vtkRPPlanningLogic> logic;
  logic->SetScene(scene);
  qRPPlanningPanel panel(logic);
  panel.VolumeComboBox()->setCurrentIndex(panel.VolumeComboBox()->findText("CT"));

  auto* tunnel = vtkRPTrajectoryNode::SafeDownCast(panel.NewPlan("vtkRPTrajectoryNode"));
  ASSERT_NE(tunnel, nullptr);
  EXPECT_EQ(tunnel->GetNumberOfControlPoints(), 0);  // the views place it next
  const double entry[3] = {0, 0, -25}, target[3] = {0, 0, 15};
  tunnel->SetEntryAndTarget(entry, target);  // what two clicks do
  Wait(100);
  EXPECT_NE(panel.FiguresText().indexOf("Length 40.0 mm"), -1) << panel.FiguresText().toStdString();
  EXPECT_NEAR(panel.Figures().LengthInBoneMm, 35, 0.6);
  EXPECT_EQ(panel.ClearanceTable()->rowCount(), 0);  // nothing at risk yet

  // A drag: the target moves in small steps; the figures follow at the panel's display rate.
  const int before = panel.NumberOfFigureUpdates();
  for (int step = 1; step <= 5; ++step) {
    const double moved[3] = {0, 0, 15.0 - step};
    tunnel->SetNthControlPointPositionWorld(vtkRPTrajectoryNode::TargetIndex, moved);
    Wait(50);
  }
  EXPECT_GE(panel.NumberOfFigureUpdates() - before, 5);
  EXPECT_NEAR(panel.Figures().LengthMm, 35, 1e-9);

  // The vessel at risk with a 13 mm margin, stored on the model: its clearance 16 - 3 - 1 = 12 mm is under it.
  QTableWidget* structures = panel.StructureTable();
  int row = -1;
  for (int r = 0; r < structures->rowCount(); ++r)
    if (structures->item(r, 0)->text() == "Vessel") row = r;
  ASSERT_GE(row, 0);
  structures->item(row, 2)->setText("13");
  structures->item(row, 1)->setCheckState(Qt::Checked);
  EXPECT_TRUE(vessel->GetProtection().Protected);
  EXPECT_EQ(vessel->GetProtection().SafetyMarginMm, 13);
  Wait(50);
  ASSERT_EQ(panel.ClearanceTable()->rowCount(), 1);
  ASSERT_EQ(panel.Figures().Clearances.size(), 1u);
  EXPECT_NEAR(panel.Figures().Clearances[0].ClearanceMm, 12, 0.05);
  EXPECT_TRUE(panel.Figures().Clearances[0].UnderMargin);
  EXPECT_EQ(panel.ClearanceTable()->item(0, 1)->foreground().color(), QColor(192, 57, 43));

  // Propose from the patch: the risk map model appears with its scalar.
  panel.RegionComboBox()->setCurrentIndex(panel.RegionComboBox()->findText("Entry patch"));
  ASSERT_TRUE(panel.Propose()) << panel.ProposalText().toStdString();
  EXPECT_NE(panel.ProposalText().indexOf("entries scored"), -1);
  auto* map = vtkRPModelNode::SafeDownCast(scene->GetFirstNodeByName("Risk map"));
  ASSERT_NE(map, nullptr);
  EXPECT_NE(map->GetPolyData()->GetPointData()->GetArray("clearanceMm"), nullptr);
  // The best entry lies away from the vessel (at +R): on the patch's -R side.
  const rp::Vec3 best = logic->GetCandidates()[static_cast<size_t>(panel.LastProposal().Best.front())];
  EXPECT_LT(best.x, 0);

  // Bad input is named: the entry and target together.
  tunnel->SetEntryAndTarget(entry, entry);
  Wait(50);
  EXPECT_NE(panel.ProblemText().indexOf("zero length"), -1) << panel.ProblemText().toStdString();
}
