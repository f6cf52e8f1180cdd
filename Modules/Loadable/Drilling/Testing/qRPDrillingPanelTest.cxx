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
#include "rpTestTime.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace {
// Labels on a 1 mm grid centred at the origin: trabecular bone for |R|,|A| <= 10, −2 <= S <= 12;
// a protected layer under it (−6 <= S < −2).
void AddSegmentation(vtkRPScene* scene) {
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(36, 36, 36);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  for (int k = 0; k < 36; ++k)
    for (int j = 0; j < 36; ++j)
      for (int i = 0; i < 36; ++i) {
        const double r = i - 18, a = j - 18, s = k - 16;
        const bool box = std::fabs(r) <= 10 && std::fabs(a) <= 10;
        static_cast<unsigned char*>(labels->GetScalarPointer(i, j, k))[0] =
            box && s >= -2 && s <= 12 ? 1 : (box && s >= -6 && s < -2 ? 2 : 0);
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
