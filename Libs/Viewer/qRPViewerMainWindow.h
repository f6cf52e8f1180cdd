#pragma once
// The main window: the views in a layout (4-up, one-up 3D, one-up slice), the module panels on
// the left (from the loaded modules, plus the viewer's own Data panel), the File menu (DICOM
// folder, data files, scenes, recent files) and a 30 Hz timer that renders only the views whose
// content changed. Nothing here waits on another thread.
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <QMainWindow>
#include <QPointer>
#include <QString>
#include <QTimer>

#include <vtkSmartPointer.h>

#include "rpRenderScheduler.h"
#include "rpSliceGeometry.h"

class QAction;
class QComboBox;
class QDragEnterEvent;
class QDropEvent;
class QMenu;
class QSlider;
class QToolBox;
class QTreeWidget;
class QTreeWidgetItem;
class QVTKOpenGLNativeWidget;
class QWidget;
class vtkCallbackCommand;
class vtkObject;
class vtkRPScene;

namespace rp {
class ModuleManager;
class ViewController;
}  // namespace rp

class qRPViewerMainWindow : public QMainWindow {
  Q_OBJECT

 public:
  qRPViewerMainWindow(rp::ModuleManager* manager, vtkRPScene* scene, QWidget* parent = nullptr);
  ~qRPViewerMainWindow() override;

  rp::ViewController* GetController() const { return this->Controller.get(); }
  QVTKOpenGLNativeWidget* GetViewWidget(rp::ViewKind kind) const { return this->ViewWidgets[static_cast<size_t>(kind)]; }
  QToolBox* GetPanelBox() const { return this->Panels; }
  QTreeWidget* GetDataTree() const { return this->DataTree; }

  /// Loads a scene or data file; adds it to the recent files. False with a message on failure
  /// (nothing already loaded is lost). Data files and DICOM series are read on a worker thread
  /// behind a progress dialog that can cancel (the event loop keeps running; the scene changes
  /// only here, on the main thread, once the read succeeded). A cancelled load returns false
  /// with the error "cancelled" and leaves the scene unchanged.
  /// `dicomObject`: for a DICOM folder, the one object to read (an image stack's ID, a SEG's or
  /// RTSTRUCT's SeriesInstanceUID, as `roboplan dicom` lists them); empty: all the folder holds.
  bool LoadFile(const QString& path, QString* error = nullptr, const QString& dicomObject = QString());
  /// Sets the scene's layout node's arrangement (vtkRPLayoutNode::Arrangement) and shows it.
  void SetViewLayout(int layout);
  /// Renders the views that asked for it; returns how many were rendered.
  int RenderPendingViews();
  static QStringList RecentFiles();

 public slots:
  void OpenDataFiles();
  /// File > Load <kind>: the same loader with the kind's file filter.
  void OpenDataFilesOfKind(const QString& title, const QString& filter);
  void OpenScene();
  void SaveSceneAs();
  /// File > Load DICOM folder: scans the folder (worker thread), lets the user pick the whole
  /// folder or one of its image stacks, SEGs or RTSTRUCTs, and loads it through LoadFile.
  void OpenDicomFolder();
  /// The folder's choices as OpenDicomFolder offers them: a label and the object ID LoadFile
  /// takes ("" for the whole folder, listed first when the folder holds several objects).
  /// Empty with `error` when the scan failed or found nothing to load.
  std::vector<std::pair<QString, QString>> DicomFolderChoices(const QString& folder, QString* error = nullptr);
  void CloseScene();

 protected:
  /// Files dropped on the window load like File > Load.
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;

 private:
  static void OnSceneChanged(vtkObject*, unsigned long, void* clientData, void*);
  void BuildViews();
  void BuildMenus();
  void BuildPanels(rp::ModuleManager* manager);
  QWidget* BuildDataPanel();
  void RefreshDataPanel();
  void RefreshVolumeCombos();
  std::string ShownLayersKey() const;
  void ApplyLayout();
  void RefreshParentTransformCombo();
  void AddRecentFile(const QString& path);
  void RebuildRecentMenu();
  void ShowProblem(const QString& title, const QString& text);
  /// LoadFile, with a message box for a failure (not for a cancel).
  void LoadAndReport(const QString& path, const QString& title);

  vtkRPScene* Scene;
  std::unique_ptr<rp::ViewController> Controller;
  std::array<QVTKOpenGLNativeWidget*, 4> ViewWidgets{};
  QWidget* ViewArea = nullptr;
  QToolBox* Panels = nullptr;
  QTreeWidget* DataTree = nullptr;
  QComboBox* BackgroundCombo = nullptr;
  QComboBox* ForegroundCombo = nullptr;
  QSlider* OpacitySlider = nullptr;
  QComboBox* FollowCombo = nullptr;
  QComboBox* ParentTransformCombo = nullptr;
  QMenu* RecentMenu = nullptr;
  QAction* PlaceFiducialAction = nullptr;
  QTimer RenderTimer;
  rp::RenderScheduler Scheduler;
  vtkSmartPointer<vtkCallbackCommand> SceneCallback;
  std::vector<unsigned long> SceneTags;
  vtkSmartPointer<vtkCallbackCommand> LayoutCallback;
  unsigned long LayoutTag = 0;
  bool LayoutDirty = false;
  std::string ShownLayers;  // background|foreground|followed|opacity as the combos show them
  bool DataPanelDirty = true;
  bool UpdatingPanel = false;
};
