// Scripted GUI test of the main window (QTest under Xvfb): load a synthetic volume and model
// from files, click in a slice view and check the other views moved to the clicked point,
// scroll, change window/level by dragging, toggle the model, place a fiducial by click, switch
// layouts, and check that only views whose content changed are rendered.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QSettings>
#include <QSurfaceFormat>
#include <QTest>
#include <QToolBox>
#include <QTreeWidget>
#include <QVTKOpenGLNativeWidget.h>
#include <QWheelEvent>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkRenderer.h>

#include "rpModuleManager.h"
#include "rpNodeStorage.h"
#include "rpView.h"
#include "rpViewController.h"
#include "qRPViewerMainWindow.h"
#include "rpViewerTestScene.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelDisplayableManager.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPViewState.h"

using namespace rp;

namespace {

QApplication& Application() {
  static int argc = 1;
  static char name[] = "qRPViewerMainWindowTest";
  static char* argv[] = {name, nullptr};
  static QApplication* application = [] {
    QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
    auto* app = new QApplication(argc, argv);
    QApplication::setOrganizationName("RoboPlanTest");
    QApplication::setApplicationName("qRPViewerMainWindowTest");
    return app;
  }();
  return *application;
}

QPoint Center(QWidget* widget) { return QPoint(widget->width() / 2, widget->height() / 2); }

// Size of one screen pixel in mm in a slice view (parallel projection).
double PixelSize(View* view, QWidget* widget) {
  return 2.0 * view->GetRenderer()->GetActiveCamera()->GetParallelScale() / widget->height();
}

void Drag(QWidget* widget, QPoint from, QPoint to) {
  QTest::mousePress(widget, Qt::LeftButton, Qt::NoModifier, from);
  QMouseEvent move(QEvent::MouseMove, to, widget->mapToGlobal(to), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(widget, &move);
  QTest::mouseRelease(widget, Qt::LeftButton, Qt::NoModifier, to);
}

}  // namespace

TEST(qRPViewerMainWindow, ScriptedSession) {
  Application();
  QSettings().clear();
  vtkNew<vtkRPScene> scene;
  qRPViewerMainWindow window(nullptr, scene);
  window.resize(1100, 800);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));

  // Load data files the way a user does.
  const std::filesystem::path dir = ROBOPLAN_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  std::string error;
  ASSERT_TRUE(SaveDataFile(test::MakeVolume(), (dir / "ct.nrrd").string(), error)) << error;
  ASSERT_TRUE(SaveDataFile(test::MakeSphereModel(), (dir / "femur.vtp").string(), error)) << error;
  QString message;
  ASSERT_TRUE(window.LoadFile(QString::fromStdString((dir / "ct.nrrd").string()), &message)) << message.toStdString();
  ASSERT_TRUE(window.LoadFile(QString::fromStdString((dir / "femur.vtp").string()), &message)) << message.toStdString();
  EXPECT_FALSE(window.LoadFile(QString::fromStdString((dir / "missing.nrrd").string()), &message));
  EXPECT_FALSE(message.isEmpty());
  int dataNodes = 0;
  for (vtkRPNode* node : scene->GetNodes()) dataNodes += node->GetHideFromEditors() ? 0 : 1;
  EXPECT_EQ(dataNodes, 2);
  EXPECT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);  // the views' nodes, not in the Data panel
  EXPECT_EQ(qRPViewerMainWindow::RecentFiles().size(), 2);
  EXPECT_TRUE(qRPViewerMainWindow::RecentFiles().front().endsWith("femur.vtp"));
  QTest::qWait(120);  // the 30 Hz timer renders and refreshes the Data panel

  ViewController* controller = window.GetController();
  vtkRPViewState* state = controller->GetViewState();
  auto* volume = controller->GetBackgroundVolume();
  ASSERT_NE(volume, nullptr);
  auto* model = vtkRPModelNode::SafeDownCast(scene->GetNodesByClass("vtkRPModelNode").at(0));
  ASSERT_NE(model, nullptr);

  // Nothing changed since the last tick: nothing to render.
  EXPECT_EQ(window.RenderPendingViews(), 0);

  // Click in the axial view's centre: the point under it is the volume centre (camera fit);
  // sagittal and coronal move there, the axial slice stays.
  const double start[3] = {test::Center[0] + 15, test::Center[1] - 10, test::Center[2] + 5};
  controller->SetSlicePointRAS(start);
  QVTKOpenGLNativeWidget* axial = window.GetViewWidget(ViewKind::Axial);
  View* axialView = controller->GetView(ViewKind::Axial);
  const double pixel = PixelSize(axialView, axial);
  QTest::mouseClick(axial, Qt::LeftButton, Qt::NoModifier, Center(axial));
  double point[3];
  controller->GetSlicePointRAS(point);
  EXPECT_NEAR(point[0], test::Center[0], 1.5 * pixel);
  EXPECT_NEAR(point[1], test::Center[1], 1.5 * pixel);
  EXPECT_DOUBLE_EQ(point[2], start[2]);
  EXPECT_DOUBLE_EQ(controller->GetView(ViewKind::Sagittal)->GetSliceOffset(), point[0]);
  EXPECT_DOUBLE_EQ(controller->GetView(ViewKind::Coronal)->GetSliceOffset(), point[1]);
  EXPECT_GE(window.RenderPendingViews(), 3);  // the three slice views (crosshair) at least

  // Click 40 pixels right of the centre in the axial view: patient left (R decreases).
  QTest::mouseClick(axial, Qt::LeftButton, Qt::NoModifier, Center(axial) + QPoint(40, 0));
  controller->GetSlicePointRAS(point);
  EXPECT_NEAR(point[0], test::Center[0] - 40 * pixel, 1.5 * pixel);

  // Scroll one notch in the axial view: up one step (2 mm) along S.
  QWheelEvent wheel(QPointF(Center(axial)), QPointF(axial->mapToGlobal(Center(axial))), QPoint(), QPoint(0, 120),
                    Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
  QApplication::sendEvent(axial, &wheel);
  double scrolled[3];
  controller->GetSlicePointRAS(scrolled);
  EXPECT_DOUBLE_EQ(scrolled[2], point[2] + 2.0);

  // Keyboard: Down moves the axial slice one step back, + zooms in by 1.2.
  axial->setFocus();
  QTest::keyClick(axial, Qt::Key_Down);
  controller->GetSlicePointRAS(scrolled);
  EXPECT_DOUBLE_EQ(scrolled[2], point[2]);
  const double scale = axialView->GetRenderer()->GetActiveCamera()->GetParallelScale();
  QTest::keyClick(axial, Qt::Key_Plus);
  EXPECT_NEAR(axialView->GetRenderer()->GetActiveCamera()->GetParallelScale(), scale / 1.2, 1e-9);
  QTest::keyClick(axial, Qt::Key_Minus);
  EXPECT_NEAR(axialView->GetRenderer()->GetActiveCamera()->GetParallelScale(), scale, 1e-9);

  // Window/level by dragging 60 pixels right in the sagittal view: the window widens by
  // 60 × (scalar range / 500); the level stays.
  QVTKOpenGLNativeWidget* sagittal = window.GetViewWidget(ViewKind::Sagittal);
  double range[2];
  volume->GetImageData()->GetScalarRange(range);
  const double window0 = volume->GetWindow(), level0 = volume->GetLevel();
  Drag(sagittal, Center(sagittal), Center(sagittal) + QPoint(60, 0));
  EXPECT_NEAR(volume->GetWindow(), window0 + 60 * (range[1] - range[0]) / 500.0, 1e-9);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), level0);
  // The drag did not move the slices.
  controller->GetSlicePointRAS(point);
  EXPECT_DOUBLE_EQ(point[2], scrolled[2]);

  // Toggle the model from the Data panel.
  QList<QTreeWidgetItem*> items = window.GetDataTree()->findItems(QString::fromStdString(model->GetName()), Qt::MatchExactly);
  ASSERT_EQ(items.size(), 1);
  auto* models = controller->GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPModelDisplayableManager>();
  EXPECT_TRUE(models->GetActor(model)->GetVisibility());
  items[0]->setCheckState(0, Qt::Unchecked);
  EXPECT_FALSE(model->GetVisibility());
  EXPECT_FALSE(models->GetActor(model)->GetVisibility());
  EXPECT_TRUE(controller->GetView(ViewKind::ThreeD)->NeedsRender());
  items[0]->setCheckState(0, Qt::Checked);
  EXPECT_TRUE(model->GetVisibility());
  EXPECT_TRUE(models->GetActor(model)->GetVisibility());

  // Place a fiducial by clicking the coronal view's centre: it lands at the volume centre's R
  // and S, on the current coronal slice (A).
  window.findChild<QAction*>("placeFiducials")->trigger();
  EXPECT_EQ(state->GetInteractionMode(), vtkRPViewState::ModePlaceFiducial);
  QVTKOpenGLNativeWidget* coronal = window.GetViewWidget(ViewKind::Coronal);
  const double coronalPixel = PixelSize(controller->GetView(ViewKind::Coronal), coronal);
  double before[3];
  controller->GetSlicePointRAS(before);
  QTest::mouseClick(coronal, Qt::LeftButton, Qt::NoModifier, Center(coronal));
  auto lists = scene->GetNodesByClass("vtkRPFiducialListNode");
  ASSERT_EQ(lists.size(), 1u);
  auto* list = vtkRPFiducialListNode::SafeDownCast(lists[0]);
  ASSERT_EQ(list->GetNumberOfControlPoints(), 1);
  double placed[3];
  list->GetNthControlPointPositionWorld(0, placed);
  EXPECT_NEAR(placed[0], test::Center[0], 1.5 * coronalPixel);
  EXPECT_NEAR(placed[1], before[1], 1e-9);
  EXPECT_NEAR(placed[2], test::Center[2], 1.5 * coronalPixel);
  double after[3];
  controller->GetSlicePointRAS(after);
  EXPECT_DOUBLE_EQ(after[0], before[0]);  // placing does not navigate
  window.findChild<QAction*>("placeFiducials")->trigger();
  EXPECT_EQ(state->GetInteractionMode(), vtkRPViewState::ModeNavigate);

  // Drag the fiducial 30 pixels right in the coronal view: it moves to patient left (−R) by
  // 30 pixels' worth of mm, staying on the slice; the slice point does not move.
  Drag(coronal, Center(coronal), Center(coronal) + QPoint(30, 0));
  double moved[3];
  list->GetNthControlPointPositionWorld(0, moved);
  EXPECT_NEAR(moved[0], placed[0] - 30 * coronalPixel, 1.5 * coronalPixel);
  EXPECT_NEAR(moved[1], placed[1], 1e-9);
  EXPECT_NEAR(moved[2], placed[2], 1.5 * coronalPixel);
  controller->GetSlicePointRAS(after);
  EXPECT_DOUBLE_EQ(after[0], before[0]);
  EXPECT_EQ(list->GetNumberOfControlPoints(), 1);

  // Layouts.
  window.findChild<QAction*>("layout_3d")->trigger();
  QTest::qWait(50);
  EXPECT_FALSE(axial->isVisible());
  EXPECT_TRUE(window.GetViewWidget(ViewKind::ThreeD)->isVisible());
  window.findChild<QAction*>("layout_axial")->trigger();
  QTest::qWait(50);
  EXPECT_TRUE(axial->isVisible());
  EXPECT_FALSE(window.GetViewWidget(ViewKind::ThreeD)->isVisible());
  window.findChild<QAction*>("layout_4up")->trigger();
  QTest::qWait(50);
  EXPECT_TRUE(sagittal->isVisible());
  EXPECT_TRUE(window.GetViewWidget(ViewKind::ThreeD)->isVisible());
  // The layout is the scene's: a module changing the layout node changes the window.
  controller->GetLayoutNode()->SetViewArrangement(vtkRPLayoutNode::OneUpCoronal);
  QTest::qWait(80);
  EXPECT_TRUE(coronal->isVisible());
  EXPECT_FALSE(sagittal->isVisible());
  EXPECT_TRUE(window.findChild<QAction*>("layout_coronal")->isChecked());
  window.findChild<QAction*>("layout_4up")->trigger();
  QTest::qWait(50);
  EXPECT_EQ(controller->GetLayoutNode()->GetViewArrangement(), vtkRPLayoutNode::FourUp);
  // Put the model under a transform from the Data panel: select it, pick the transform.
  vtkNew<vtkRPLinearTransformNode> lift;
  lift->SetName("Lift");
  scene->AddNode(lift);
  QTest::qWait(60);  // the Data panel refreshes on the timer
  items = window.GetDataTree()->findItems(QString::fromStdString(model->GetName()), Qt::MatchExactly);
  ASSERT_EQ(items.size(), 1);
  window.GetDataTree()->setCurrentItem(items[0]);
  auto* parentCombo = window.findChild<QComboBox*>("parentTransform");
  ASSERT_NE(parentCombo, nullptr);
  ASSERT_TRUE(parentCombo->isEnabled());
  const int liftIndex = parentCombo->findText("Lift");
  ASSERT_GE(liftIndex, 0);
  parentCombo->setCurrentIndex(liftIndex);
  emit parentCombo->activated(liftIndex);
  EXPECT_EQ(model->GetTransformNodeID(), lift->GetID());

  // A tool streaming at 1 kHz between two display ticks: the slices follow its tip, and each
  // view renders once per tick however many poses arrived.
  vtkNew<vtkRPTrackedToolNode> stylus;
  stylus->SetName("StylusTip");
  scene->AddNode(stylus);
  controller->SetFollowTransformNodeID(stylus->GetID());
  QTest::qWait(60);
  window.RenderPendingViews();
  vtkNew<vtkMatrix4x4> pose;
  for (int i = 0; i < 33; ++i) {
    pose->SetElement(0, 3, test::Center[0] + 0.1 * i);
    pose->SetElement(1, 3, test::Center[1]);
    pose->SetElement(2, 3, test::Center[2] - 0.2 * i);
    stylus->SetMatrixTransformToParent(pose);
  }
  controller->GetSlicePointRAS(point);
  EXPECT_DOUBLE_EQ(point[0], test::Center[0] + 3.2);
  EXPECT_DOUBLE_EQ(point[2], test::Center[2] - 6.4);
  EXPECT_EQ(window.RenderPendingViews(), 4);  // axial, sagittal, coronal, 3D: once each
  EXPECT_EQ(window.RenderPendingViews(), 0);
  controller->SetFollowTransformNodeID("");

  // A picture of the session for people reading the test output.
  QTest::qWait(100);
  window.grab().save(QString::fromStdString((dir / "mainwindow.png").string()));
  QSettings().clear();
}

// The project's modules in the viewer: each module's panel comes from its panel plugin (loaded
// only now: a command never loads them), in the Modules dock after the Data panel.
TEST(ViewerMainWindow, ShowsEveryModulesPanelFromItsPlugin) {
  Application();
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  ASSERT_GE(manager.LoadModules({ROBOPLAN_BINARY_DIR "/lib/roboplan-modules"}, scene), 9);
  qRPViewerMainWindow window(&manager, scene);
  auto* panels = window.findChild<QToolBox*>();
  ASSERT_NE(panels, nullptr);
  QStringList titles;
  for (int i = 0; i < panels->count(); ++i) titles << panels->itemText(i);
  for (const char* title : {"Data", "Segmentation to Mesh", "Landmark Registration", "Haptics", "Tracking", "Navigation",
                            "Drilling", "Planning"})
    EXPECT_TRUE(titles.contains(title)) << title << " missing from " << titles.join(", ").toStdString();
  EXPECT_TRUE(manager.GetFailures().empty()) << manager.GetFailures()[0].Path << ": " << manager.GetFailures()[0].Reason;
}
