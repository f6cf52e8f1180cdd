// The Tracking panel on the built-in simulator: connect, tools OK in the table and the scene,
// pivot calibration recovers the Stylus tip offset, disconnect.
#include <gtest/gtest.h>

#include <QApplication>
#include <QTableWidget>
#include <QThread>

#include <vtkNew.h>

#include "qRPTrackingPanel.h"
#include "rpToolDefinition.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"
#include "vtkRPLinearTransformNode.h"
#include <vtkMatrix4x4.h>

TEST(TrackingPanel, SimulatorConnectTableAndPivot) {
  int argc = 1;
  char name[] = "qRPTrackingPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  qRPTrackingPanel panel(logic);
  panel.show();
  const QString tools = QString(ROBOPLAN_RESOURCES_DIR) + "/Tools/";
  ASSERT_TRUE(panel.ConnectSource("simulator", "", {tools + "Stylus.json", tools + "Reference.json"}))
      << panel.StatusText().toStdString();
  auto pump = [&](double seconds) {
    const double end = rp::SteadySeconds() + seconds;
    while (rp::SteadySeconds() < end) {
      app.processEvents();
      QThread::msleep(5);
    }
  };
  pump(1.5);
  EXPECT_TRUE(panel.StatusText().contains("tracking")) << panel.StatusText().toStdString();
  ASSERT_EQ(panel.ToolTable()->rowCount(), 2);
  EXPECT_EQ(panel.ToolTable()->item(0, 0)->text(), "StylusToTracker");
  EXPECT_EQ(panel.ToolTable()->item(0, 1)->text(), "OK");
  auto* stylus = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName("StylusToTracker"));
  ASSERT_NE(stylus, nullptr);
  EXPECT_EQ(stylus->GetStatus(), vtkRPTrackedToolNode::StatusOK);

  panel.StartPivotCalibration(2.0);
  pump(2.3);
  EXPECT_TRUE(panel.PivotText().contains("accepted")) << panel.PivotText().toStdString();
  auto* tip = vtkRPLinearTransformNode::SafeDownCast(scene->GetFirstNodeByName("StylusTipToStylus"));
  ASSERT_NE(tip, nullptr);
  EXPECT_EQ(tip->GetTransformNodeID(), stylus->GetID());
  const rp::ToolDefinition truth = rp::ReadToolDefinition((tools + "Stylus.json").toStdString());
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(tip->GetMatrixTransformToParent()->GetElement(k, 3), truth.TipOffset[static_cast<size_t>(k)], 0.5);
  panel.Disconnect();
  EXPECT_FALSE(panel.IsConnected());
  EXPECT_EQ(panel.StatusText(), "not connected");
}
