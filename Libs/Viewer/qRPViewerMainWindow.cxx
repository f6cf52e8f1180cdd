#include "qRPViewerMainWindow.h"

#include <algorithm>

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QGridLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QToolBar>
#include <QToolBox>
#include <QTreeWidget>
#include <QUrl>
#include <QVBoxLayout>
#include <QVTKOpenGLNativeWidget.h>

#include <vtkCallbackCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderWindowInteractor.h>

#include "rpBackgroundRead.h"
#include "rpDataLoader.h"
#include "rpModuleManager.h"
#include "rpNodeStorage.h"
#include "rpSceneFormats.h"
#include "rpSceneIO.h"
#include "rpView.h"
#include "rpViewController.h"
#include "rpViewerApplication.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceInteractorStyle.h"
#include "vtkRPTransformableNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPViewState.h"

#ifdef ROBOPLAN_VIEWER_HAVE_DICOM
#include "rpDicomEntries.h"
#include "rpDicomSeries.h"
#endif

namespace rp {

namespace {
constexpr int RefreshIntervalMs = 33;  // ~30 Hz
constexpr int MaxRecentFiles = 8;
const char* const RecentFilesKey = "recentFiles";

// "*.nrrd *.nii.gz ..." for a file dialog: every extension the storages read for these classes.
QString FilePatterns(std::initializer_list<const char*> nodeClasses) {
  QStringList patterns;
  for (const char* nodeClass : nodeClasses)
    for (const std::string& extension : ExtensionsForNodeClass(nodeClass)) patterns << "*" + QString::fromStdString(extension);
  patterns.removeDuplicates();
  return patterns.join(' ');
}
}  // namespace
}  // namespace rp

using namespace rp;  // the viewer's types (ModuleManager, ViewController, ViewKind...)

qRPViewerMainWindow::qRPViewerMainWindow(ModuleManager* manager, vtkRPScene* scene, QWidget* parent)
    : QMainWindow(parent), Scene(scene), Controller(std::make_unique<ViewController>(scene)) {
  this->setWindowTitle("RoboPlan");
  this->BuildViews();
  this->BuildPanels(manager);
  this->BuildMenus();

  this->SceneCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->SceneCallback->SetClientData(this);
  this->SceneCallback->SetCallback(&qRPViewerMainWindow::OnSceneChanged);
  for (unsigned long event : {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeRemovedEvent}) {
    this->SceneTags.push_back(scene->AddObserver(event, this->SceneCallback));
  }
  this->LayoutCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->LayoutCallback->SetClientData(this);
  this->LayoutCallback->SetCallback(
      [](vtkObject*, unsigned long, void* clientData, void*) { static_cast<qRPViewerMainWindow*>(clientData)->LayoutDirty = true; });
  this->LayoutTag = this->Controller->GetLayoutNode()->AddObserver(vtkCommand::ModifiedEvent, this->LayoutCallback);
  this->ApplyLayout();

  // Render at display rate, only what changed; the timer never waits on anything.
  connect(&this->RenderTimer, &QTimer::timeout, this, [this]() {
    // The controller ends placing by itself (a plan placed in full, a new plan to place): the
    // toolbar's button follows the view state.
    const bool placing = this->Controller->GetViewState()->GetInteractionMode() == vtkRPViewState::ModePlaceFiducial;
    if (this->PlaceFiducialAction && this->PlaceFiducialAction->isChecked() != placing) {
      const QSignalBlocker blocker(this->PlaceFiducialAction);
      this->PlaceFiducialAction->setChecked(placing);
    }
    if (this->LayoutDirty) {
      this->LayoutDirty = false;
      this->ApplyLayout();
    }
    if (this->DataPanelDirty) {
      this->RefreshDataPanel();
    } else {
      // Layers or the followed node changed from elsewhere, e.g. a module (the slice point does
      // not matter here).
      const std::string layers = this->ShownLayersKey();
      if (layers != this->ShownLayers) {
        this->UpdatingPanel = true;
        this->RefreshVolumeCombos();
        this->UpdatingPanel = false;
      }
    }
    this->RenderPendingViews();
  });
  this->RenderTimer.start(RefreshIntervalMs);
  this->setAcceptDrops(true);
  this->statusBar()->showMessage("Click: set the slice point · drag: window/level · wheel: slice · right drag: zoom · middle drag: pan");
}

qRPViewerMainWindow::~qRPViewerMainWindow() {
  this->RenderTimer.stop();
  for (unsigned long tag : this->SceneTags) this->Scene->RemoveObserver(tag);
  this->Controller->GetLayoutNode()->RemoveObserver(this->LayoutTag);
  // Views leave their render windows before the widgets go.
  for (int kind = 0; kind < 4; ++kind) this->Controller->GetView(static_cast<ViewKind>(kind))->DetachFromRenderWindow();
}

void qRPViewerMainWindow::OnSceneChanged(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<qRPViewerMainWindow*>(clientData)->DataPanelDirty = true;
}

void qRPViewerMainWindow::BuildViews() {
  this->ViewArea = new QWidget(this);
  auto* grid = new QGridLayout(this->ViewArea);
  grid->setContentsMargins(0, 0, 0, 0);
  grid->setSpacing(2);
  const int rows[4] = {0, 1, 1, 0}, columns[4] = {0, 0, 1, 1};  // axial, sagittal, coronal, 3D
  const double full[4] = {0, 0, 1, 1};
  for (int kind = 0; kind < 4; ++kind) {
    auto* widget = new QVTKOpenGLNativeWidget(this->ViewArea);
    widget->setObjectName(QString("%1View").arg(GetViewName(static_cast<ViewKind>(kind))));
    widget->setMinimumSize(120, 120);
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    window->SetMultiSamples(0);
    widget->setRenderWindow(window);
    View* view = this->Controller->GetView(static_cast<ViewKind>(kind));
    view->AttachToRenderWindow(window, full);
    if (view->IsSlice()) {
      vtkNew<vtkRPSliceInteractorStyle> style;
      style->SetController(this->Controller.get(), view->GetKind());
      widget->interactor()->SetInteractorStyle(style);
    } else {
      vtkNew<vtkRPThreeDInteractorStyle> style;
      style->SetController(this->Controller.get());
      widget->interactor()->SetInteractorStyle(style);
    }
    grid->addWidget(widget, rows[kind], columns[kind]);
    this->ViewWidgets[static_cast<size_t>(kind)] = widget;
    // Rendered by the display-rate timer: once per tick at most, only when changed, light while
    // moving (rp::RenderScheduler).
    this->Scheduler.AddView(
        view, [view, widget]() {
          view->MarkRendered();
          widget->renderWindow()->Render();
        },
        [widget]() { return widget->isVisible(); });
  }
  this->setCentralWidget(this->ViewArea);
}

void qRPViewerMainWindow::SetViewLayout(int layout) {
  this->Controller->GetLayoutNode()->SetViewArrangement(layout);  // the layout observer applies it
  this->ApplyLayout();
}

// Shows the views of the scene's layout node (set here, by a loaded scene or by a module).
void qRPViewerMainWindow::ApplyLayout() {
  const int layout = this->Controller->GetLayoutNode()->GetViewArrangement();
  if (QAction* action = this->findChild<QAction*>(QString("layout_%1").arg(vtkRPLayoutNode::GetArrangementAsString(layout)))) {
    action->setChecked(true);
  }
  for (int kind = 0; kind < 4; ++kind) {
    bool visible = true;
    switch (layout) {
      case vtkRPLayoutNode::OneUp3D: visible = kind == int(ViewKind::ThreeD); break;
      case vtkRPLayoutNode::OneUpAxial: visible = kind == int(ViewKind::Axial); break;
      case vtkRPLayoutNode::OneUpSagittal: visible = kind == int(ViewKind::Sagittal); break;
      case vtkRPLayoutNode::OneUpCoronal: visible = kind == int(ViewKind::Coronal); break;
      default: break;
    }
    this->ViewWidgets[static_cast<size_t>(kind)]->setVisible(visible);
    this->Controller->GetView(static_cast<ViewKind>(kind))->RequestRender();
  }
}

int qRPViewerMainWindow::RenderPendingViews() { return this->Scheduler.RenderPendingViews(); }

void qRPViewerMainWindow::BuildMenus() {
  QMenu* file = this->menuBar()->addMenu("&File");
  QAction* dicom = file->addAction("Load &DICOM folder...", this, &qRPViewerMainWindow::OpenDicomFolder);
#ifndef ROBOPLAN_VIEWER_HAVE_DICOM
  dicom->setEnabled(false);
  dicom->setToolTip("This build has no DICOM reader (Libs/Imaging's rpDicomSeries was not available)");
#else
  (void)dicom;
#endif
  file->addAction("&Load data (volume, segmentation, model, fiducials, transform)...", this,
                  &qRPViewerMainWindow::OpenDataFiles, QKeySequence::Open);
  // The formats are the storage registry's (rpNodeStorage), not a list of our own.
  const std::pair<const char*, const char*> kinds[] = {{"Load &volume...", "vtkRPScalarVolumeNode"},
                                                       {"Load se&gmentation...", "vtkRPSegmentationNode"},
                                                       {"Load &model...", "vtkRPModelNode"},
                                                       {"Load &fiducials...", "vtkRPFiducialListNode"},
                                                       {"Load &transform...", "vtkRPLinearTransformNode"}};
  for (const auto& [title, nodeClass] : kinds) {
    const QString caption = QString(title).remove('&').remove("...");
    const QString files = caption.mid(caption.indexOf(' ') + 1) + "s (" + FilePatterns({nodeClass}) + ")";
    file->addAction(title, this, [this, caption, files]() { this->OpenDataFilesOfKind(caption, files); });
  }
  file->addAction("Load &scene...", this, &qRPViewerMainWindow::OpenScene);
  file->addAction("&Save scene as...", this, &qRPViewerMainWindow::SaveSceneAs, QKeySequence::SaveAs);
  this->RecentMenu = file->addMenu("&Recent files");
  this->RebuildRecentMenu();
  file->addSeparator();
  file->addAction("&Close scene", this, &qRPViewerMainWindow::CloseScene);
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);

  QToolBar* toolbar = this->addToolBar("Views");
  toolbar->setObjectName("ViewsToolBar");
  QMenu* viewMenu = this->menuBar()->addMenu("&View");
  auto* layouts = new QActionGroup(this);
  const std::pair<const char*, int> layoutActions[] = {{"4-up", vtkRPLayoutNode::FourUp},
                                                       {"3D", vtkRPLayoutNode::OneUp3D},
                                                       {"Axial", vtkRPLayoutNode::OneUpAxial},
                                                       {"Sagittal", vtkRPLayoutNode::OneUpSagittal},
                                                       {"Coronal", vtkRPLayoutNode::OneUpCoronal}};
  for (const auto& [name, layout] : layoutActions) {
    QAction* action = viewMenu->addAction(name);
    action->setCheckable(true);
    action->setChecked(layout == this->Controller->GetLayoutNode()->GetViewArrangement());
    action->setObjectName(QString("layout_%1").arg(vtkRPLayoutNode::GetArrangementAsString(layout)));
    layouts->addAction(action);
    toolbar->addAction(action);
    const int chosen = layout;
    connect(action, &QAction::triggered, this, [this, chosen]() { this->SetViewLayout(chosen); });
  }
  toolbar->addSeparator();
  QAction* reset = viewMenu->addAction("&Reset views", this, [this]() { this->Controller->ResetViews(); });
  toolbar->addAction(reset);
  QAction* slicesIn3D = viewMenu->addAction("Slices in 3D");
  slicesIn3D->setObjectName("slicesIn3D");
  slicesIn3D->setCheckable(true);
  slicesIn3D->setChecked(this->Controller->GetSlicesVisibleIn3D());
  connect(slicesIn3D, &QAction::toggled, this, [this](bool on) { this->Controller->SetSlicesVisibleIn3D(on); });
  toolbar->addAction(slicesIn3D);
  this->PlaceFiducialAction = toolbar->addAction("Place fiducials");
  this->PlaceFiducialAction->setObjectName("placeFiducials");
  this->PlaceFiducialAction->setCheckable(true);
  this->PlaceFiducialAction->setToolTip(
      "Clicks in the views add points to the active fiducial list, or place a new plan's points (a trajectory's entry "
      "then target)");
  connect(this->PlaceFiducialAction, &QAction::toggled, this, [this](bool on) {
    this->Controller->GetViewState()->SetInteractionMode(on ? vtkRPViewState::ModePlaceFiducial
                                                            : vtkRPViewState::ModeNavigate);
  });
  auto* presets = new QComboBox(toolbar);
  presets->setObjectName("windowLevelPresets");
  presets->addItems({"Window/level preset...", "CT bone", "CT soft tissue", "MR"});
  connect(presets, QOverload<int>::of(&QComboBox::activated), this, [this, presets](int index) {
    if (index == 1) this->Controller->ApplyWindowLevelPreset(WindowLevelPreset::CTBone);
    if (index == 2) this->Controller->ApplyWindowLevelPreset(WindowLevelPreset::CTSoftTissue);
    if (index == 3) this->Controller->ApplyWindowLevelPreset(WindowLevelPreset::MR);
    presets->setCurrentIndex(0);
  });
  toolbar->addWidget(presets);
}

void qRPViewerMainWindow::BuildPanels(ModuleManager* manager) {
  auto* dock = new QDockWidget("Modules", this);
  dock->setObjectName("ModulesDock");
  dock->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable);
  this->Panels = new QToolBox(dock);
  this->Panels->addItem(this->BuildDataPanel(), "Data");
  if (manager) {
    for (Module* module : manager->GetModules()) {
      QWidget* panel = manager->CreatePanel(module->Name(), this->Scene, this->Panels);
      if (panel) this->Panels->addItem(panel, QString::fromStdString(module->Title()));
    }
  }
  dock->setWidget(this->Panels);
  dock->setMinimumWidth(300);
  this->addDockWidget(Qt::LeftDockWidgetArea, dock);
}

QWidget* qRPViewerMainWindow::BuildDataPanel() {
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  this->DataTree = new QTreeWidget(panel);
  this->DataTree->setObjectName("dataTree");
  this->DataTree->setHeaderLabels({"Node", "Type"});
  this->DataTree->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  layout->addWidget(this->DataTree);
  // A model's check box is its visibility.
  connect(this->DataTree, &QTreeWidget::itemChanged, this, [this](QTreeWidgetItem* item, int) {
    if (this->UpdatingPanel) return;
    auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(item->data(0, Qt::UserRole).toString().toStdString()));
    if (model) model->SetVisibility(item->checkState(0) == Qt::Checked);
  });

  // The selected node's parent transform (e.g. put the MR under MRToCT to show it registered).
  layout->addWidget(new QLabel("Transform of the selected node"));
  this->ParentTransformCombo = new QComboBox(panel);
  this->ParentTransformCombo->setObjectName("parentTransform");
  this->ParentTransformCombo->setEnabled(false);
  layout->addWidget(this->ParentTransformCombo);
  connect(this->DataTree, &QTreeWidget::currentItemChanged, this, [this]() { this->RefreshParentTransformCombo(); });
  connect(this->ParentTransformCombo, QOverload<int>::of(&QComboBox::activated), this, [this]() {
    QTreeWidgetItem* item = this->DataTree->currentItem();
    if (this->UpdatingPanel || !item) return;
    auto* node = vtkRPTransformableNode::SafeDownCast(this->Scene->GetNodeByID(item->data(0, Qt::UserRole).toString().toStdString()));
    const std::string parent = this->ParentTransformCombo->currentData().toString().toStdString();
    if (node && !node->SetAndObserveTransformNodeID(parent)) {
      this->ShowProblem("Transform", "This transform cannot be the node's parent (it would make a cycle).");
    }
    this->RefreshParentTransformCombo();
  });

  layout->addWidget(new QLabel("Background volume"));
  this->BackgroundCombo = new QComboBox(panel);
  this->BackgroundCombo->setObjectName("backgroundVolume");
  layout->addWidget(this->BackgroundCombo);
  layout->addWidget(new QLabel("Foreground volume (over the background)"));
  this->ForegroundCombo = new QComboBox(panel);
  this->ForegroundCombo->setObjectName("foregroundVolume");
  layout->addWidget(this->ForegroundCombo);
  this->OpacitySlider = new QSlider(Qt::Horizontal, panel);
  this->OpacitySlider->setObjectName("foregroundOpacity");
  this->OpacitySlider->setRange(0, 100);
  this->OpacitySlider->setValue(50);
  layout->addWidget(this->OpacitySlider);
  layout->addWidget(new QLabel("Slices follow the tip of"));
  this->FollowCombo = new QComboBox(panel);
  this->FollowCombo->setObjectName("followTransform");
  this->FollowCombo->setToolTip("Re-slice at a tracked tool's (or any transform's) origin as it moves");
  layout->addWidget(this->FollowCombo);
  connect(this->FollowCombo, QOverload<int>::of(&QComboBox::activated), this, [this]() {
    if (!this->UpdatingPanel) this->Controller->SetFollowTransformNodeID(this->FollowCombo->currentData().toString().toStdString());
  });
  auto choose = [this](QComboBox* combo, bool background) {
    if (this->UpdatingPanel) return;
    const std::string id = combo->currentData().toString().toStdString();
    if (background) {
      this->Controller->SetBackgroundVolumeID(id);
      this->Controller->ResetCameras();
    } else {
      this->Controller->SetForegroundVolumeID(id);
    }
  };
  connect(this->BackgroundCombo, QOverload<int>::of(&QComboBox::activated), this,
          [this, choose]() { choose(this->BackgroundCombo, true); });
  connect(this->ForegroundCombo, QOverload<int>::of(&QComboBox::activated), this,
          [this, choose]() { choose(this->ForegroundCombo, false); });
  connect(this->OpacitySlider, &QSlider::valueChanged, this,
          [this](int value) {
            if (!this->UpdatingPanel) this->Controller->SetForegroundOpacity(value / 100.0);
          });
  return panel;
}

void qRPViewerMainWindow::RefreshDataPanel() {
  this->DataPanelDirty = false;
  this->UpdatingPanel = true;
  this->DataTree->clear();
  for (vtkRPNode* node : this->Scene->GetNodes()) {
    if (node->GetHideFromEditors()) continue;  // the views' own nodes
    auto* item = new QTreeWidgetItem(this->DataTree);
    item->setText(0, QString::fromStdString(node->GetName()));
    item->setText(1, QString::fromStdString(node->GetNodeTagName()));
    item->setData(0, Qt::UserRole, QString::fromStdString(node->GetID()));
    if (auto* model = vtkRPModelNode::SafeDownCast(node)) {
      item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
      item->setCheckState(0, model->GetVisibility() ? Qt::Checked : Qt::Unchecked);
    }
  }
  this->RefreshVolumeCombos();
  this->RefreshParentTransformCombo();
  this->UpdatingPanel = false;
}

void qRPViewerMainWindow::RefreshParentTransformCombo() {
  const bool wasUpdating = this->UpdatingPanel;
  this->UpdatingPanel = true;
  QTreeWidgetItem* item = this->DataTree->currentItem();
  auto* node = item ? vtkRPTransformableNode::SafeDownCast(
                          this->Scene->GetNodeByID(item->data(0, Qt::UserRole).toString().toStdString()))
                    : nullptr;
  this->ParentTransformCombo->clear();
  this->ParentTransformCombo->setEnabled(node != nullptr);
  if (node) {
    this->ParentTransformCombo->addItem("(none: RAS)", QString());
    for (vtkRPNode* transform : this->Scene->GetNodesByClass("vtkRPLinearTransformNode")) {
      if (transform == node) continue;
      this->ParentTransformCombo->addItem(QString::fromStdString(transform->GetName()), QString::fromStdString(transform->GetID()));
      if (transform->GetID() == node->GetTransformNodeID()) {
        this->ParentTransformCombo->setCurrentIndex(this->ParentTransformCombo->count() - 1);
      }
    }
  }
  this->UpdatingPanel = wasUpdating;
}

std::string qRPViewerMainWindow::ShownLayersKey() const {
  vtkRPSliceNode* red = this->Controller->GetSliceNode(ViewKind::Axial);
  return red->GetBackgroundVolumeID() + "|" + red->GetForegroundVolumeID() + "|" + red->GetFollowNodeID() + "|" +
         std::to_string(red->GetForegroundOpacity());
}

void qRPViewerMainWindow::RefreshVolumeCombos() {
  vtkRPSliceNode* red = this->Controller->GetSliceNode(ViewKind::Axial);
  this->ShownLayers = this->ShownLayersKey();
  for (QComboBox* combo : {this->BackgroundCombo, this->ForegroundCombo}) {
    const std::string selected = combo == this->BackgroundCombo ? red->GetBackgroundVolumeID() : red->GetForegroundVolumeID();
    combo->clear();
    combo->addItem("(none)", QString());
    for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPScalarVolumeNode")) {
      combo->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
      if (node->GetID() == selected) combo->setCurrentIndex(combo->count() - 1);
    }
  }
  this->OpacitySlider->setValue(static_cast<int>(red->GetForegroundOpacity() * 100.0 + 0.5));
  this->FollowCombo->clear();
  this->FollowCombo->addItem("(nothing)", QString());
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPLinearTransformNode")) {
    this->FollowCombo->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
    if (node->GetID() == this->Controller->GetFollowTransformNodeID()) this->FollowCombo->setCurrentIndex(this->FollowCombo->count() - 1);
  }
}

bool qRPViewerMainWindow::LoadFile(const QString& path, QString* error, const QString& dicomObject) {
  std::string message;
  std::vector<std::string> warnings;
  bool ok = false;
  // The worker finds the reader too (for a folder that looks into every file) and reads unless
  // the path is a scene file.
  BackgroundReadResult result = RunBackgroundRead(this, "Loading " + QFileInfo(path).fileName(),
                                                  MakeDataRead(this->Scene, path.toStdString(), dicomObject.toStdString()));
  if (result.LeftToMainThread && !result.Cancelled) {
    // A scene file fills the scene as it reads: on this thread.
    QApplication::setOverrideCursor(Qt::WaitCursor);
    ok = LoadSceneOrDataFile(this->Scene, path.toStdString(), message, &warnings);
    QApplication::restoreOverrideCursor();
  } else {
    ok = result.Ok;
    message = result.Error;
    warnings = result.Warnings;
    if (ok) AddReadNodes(this->Scene, result.Nodes);  // several (a DICOM study) in one import
  }
  if (!ok) {
    if (error) *error = QString::fromStdString(message);
    return false;
  }
  // A scene reopens as saved (its slice nodes); the 3D camera frames what is now loaded.
  this->Controller->ResetCameras3D();
  for (const std::string& warning : warnings) this->statusBar()->showMessage(QString::fromStdString(warning), 10000);
  this->AddRecentFile(QFileInfo(path).absoluteFilePath());
  return true;
}

void qRPViewerMainWindow::ShowProblem(const QString& title, const QString& text) {
  QMessageBox::warning(this, title, text);
}

void qRPViewerMainWindow::LoadAndReport(const QString& path, const QString& title) {
  QString error;
  if (!this->LoadFile(path, &error) && error != "cancelled") this->ShowProblem(title, error);
}

void qRPViewerMainWindow::OpenDataFiles() {
  this->OpenDataFilesOfKind("Load data", "Data (" +
                                             FilePatterns({"vtkRPScalarVolumeNode", "vtkRPSegmentationNode",
                                                           "vtkRPModelNode", "vtkRPFiducialListNode",
                                                           "vtkRPLinearTransformNode"}) +
                                             ")");
}

void qRPViewerMainWindow::OpenDataFilesOfKind(const QString& title, const QString& filter) {
  const QStringList files = QFileDialog::getOpenFileNames(this, title, QString(), filter + ";;All files (*)");
  for (const QString& file : files) this->LoadAndReport(file, title);
}

void qRPViewerMainWindow::OpenScene() {
  const QString file = QFileDialog::getOpenFileName(this, "Load scene", QString(),
                                                    "Scenes (*.rpscene *.mrml *.mrb);;RoboPlan scene (*.rpscene);;"
                                                    "3D Slicer scene (*.mrml *.mrb)");
  if (file.isEmpty()) return;
  this->LoadAndReport(file, "Load scene");
}

void qRPViewerMainWindow::SaveSceneAs() {
  QString filter;
  QString file = QFileDialog::getSaveFileName(this, "Save scene", QString(),
                                              "RoboPlan scene (*.rpscene);;3D Slicer bundle (*.mrb)", &filter);
  if (file.isEmpty()) return;
  if (!IsSceneFileName(file.toStdString())) file += filter.contains("mrb") ? ".mrb" : SceneFileExtension;
  SceneTransferReport report;
  if (!WriteSceneFile(this->Scene, file.toStdString(), report) || !report.FirstProblem().empty()) {
    this->ShowProblem("Save scene", QString::fromStdString(report.Ok ? report.FirstProblem() : report.Error));
    if (!report.Ok) return;
  }
  this->AddRecentFile(file);
  this->statusBar()->showMessage("Saved " + file, 5000);
}

void qRPViewerMainWindow::CloseScene() {
  this->Scene->Clear();  // the views' nodes stay (singletons)
  this->Controller->ResetViews();
}

std::vector<std::pair<QString, QString>> qRPViewerMainWindow::DicomFolderChoices(const QString& folder, QString* error) {
  std::vector<std::pair<QString, QString>> choices;
#ifdef ROBOPLAN_VIEWER_HAVE_DICOM
  auto scan = std::make_shared<DicomScanResult>();
  const std::string folderPath = folder.toStdString();
  const BackgroundReadResult scanned = RunBackgroundRead(
      this, "Scanning " + QFileInfo(folder).fileName(),
      [scan, folderPath](BackgroundReadResult& result, const ProgressCallback& progress) {
        // DCMTK loads on this first scan (rpDicomEntries.h), not with the window.
        const auto scanDicom = dicom::Entry<dicom::ScanFunction>(dicom::ScanEntry, folderPath, result.Error);
        return scanDicom && scanDicom(folderPath, *scan, result.Error, progress);
      });
  if (!scanned.Ok || (scan->Series.empty() && scan->Segmentations.empty())) {
    if (error)
      *error = scanned.Cancelled ? QString("cancelled")
               : scanned.Ok     ? "No DICOM image series or segmentation in " + folder
                                : QString::fromStdString(scanned.Error);
    return choices;
  }
  // One line per object, as `roboplan dicom` lists them, problems shown.
  for (const DicomSeriesInfo& series : scan->Series) {
    QString line = QString("%1 %2 — %3, %4 (%5x%6x%7)")
                       .arg(QString::fromStdString(series.Modality), QString::fromStdString(series.SeriesNumber),
                            QString::fromStdString(series.SeriesDescription),
                            QString::fromStdString(series.OrientationName))
                       .arg(series.Columns)
                       .arg(series.Rows)
                       .arg(series.Slices);
    if (series.StackCount > 1) line += QString(" stack %1 of %2").arg(series.StackIndex).arg(series.StackCount);
    if (!series.Problem.empty()) line += " [" + QString::fromStdString(series.Problem) + "]";
    choices.emplace_back(line, QString::fromStdString(series.StackID));
  }
  for (const DicomSegmentationObjectInfo& object : scan->Segmentations)
    choices.emplace_back(QString("%1 %2 — %3 (%4 segments)")
                             .arg(QString::fromStdString(object.Kind), QString::fromStdString(object.SeriesNumber),
                                  QString::fromStdString(object.SeriesDescription))
                             .arg(object.Segments.size()),
                         QString::fromStdString(object.SeriesInstanceUID));
  if (choices.size() > 1)
    choices.insert(choices.begin(), {QString("The whole folder (%1 image stacks, %2 segmentations)")
                                         .arg(scan->Series.size())
                                         .arg(scan->Segmentations.size()),
                                     QString()});
#else
  if (error) *error = "this viewer was built without DICOM";
  (void)folder;
#endif
  return choices;
}

void qRPViewerMainWindow::OpenDicomFolder() {
  const QString folder = QFileDialog::getExistingDirectory(this, "Load DICOM folder");
  if (folder.isEmpty()) return;
  QString error;
  const std::vector<std::pair<QString, QString>> choices = this->DicomFolderChoices(folder, &error);
  if (choices.empty()) {
    if (error != "cancelled") this->ShowProblem("Load DICOM", error);
    return;
  }
  size_t index = 0;
  if (choices.size() > 1) {
    QStringList labels;
    for (const auto& choice : choices) labels << choice.first;
    bool ok = false;
    const QString chosen = QInputDialog::getItem(this, "Load DICOM", "Load:", labels, 0, false, &ok);
    if (!ok) return;
    index = static_cast<size_t>(std::max(0, labels.indexOf(chosen)));
  }
  // The loader reads the folder again (headers only) and the chosen object: one DICOM path for
  // the command line, drag and drop, and this menu.
  if (!this->LoadFile(folder, &error, choices[index].second) && error != "cancelled") this->ShowProblem("Load DICOM", error);
}

void qRPViewerMainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void qRPViewerMainWindow::dropEvent(QDropEvent* event) {
  for (const QUrl& url : event->mimeData()->urls()) {
    if (!url.isLocalFile()) continue;
    this->LoadAndReport(url.toLocalFile(), "Load");
  }
  event->acceptProposedAction();
}

QStringList qRPViewerMainWindow::RecentFiles() {
  return QSettings().value(RecentFilesKey).toStringList();
}

void qRPViewerMainWindow::AddRecentFile(const QString& path) {
  QStringList files = RecentFiles();
  files.removeAll(path);
  files.prepend(path);
  while (files.size() > MaxRecentFiles) files.removeLast();
  QSettings().setValue(RecentFilesKey, files);
  this->RebuildRecentMenu();
}

void qRPViewerMainWindow::RebuildRecentMenu() {
  if (!this->RecentMenu) return;
  this->RecentMenu->clear();
  const QStringList files = RecentFiles();
  for (const QString& file : files) {
    this->RecentMenu->addAction(file, this, [this, file]() { this->LoadAndReport(file, "Load"); });
  }
  this->RecentMenu->setEnabled(!files.isEmpty());
}
