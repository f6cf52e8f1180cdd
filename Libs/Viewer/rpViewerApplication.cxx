#include "rpViewerApplication.h"

#include <iostream>

#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkNew.h>

#include "rpDataLoader.h"
#include "rpModuleManager.h"
#include "rpNodeStorage.h"
#include "rpSceneIO.h"
#include "rpScreenshot.h"
#include "rpViewController.h"
#include "rpViewerEntries.h"
#include "rpXDisplay.h"
#include "qRPViewerMainWindow.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPLayoutNode.h"

namespace rp {

BackgroundRead MakeDataRead(vtkRPScene* scene, const std::string& path, const std::string& dicomObject) {
  // The one loader (rpDataLoader.h) on the worker thread: readers that do not read into the scene
  // only create nodes through it (a const lookup in its node registry). The lookup too: for a
  // folder it looks into every file (is one a DICOM SEG or RTSTRUCT?).
  return [scene, path, dicomObject](BackgroundReadResult& result, const ProgressCallback& progress) {
    const DataReader* reader = FindDataReader(path);
    if (reader && reader->ReadsIntoScene()) {
      result.LeftToMainThread = true;
      return false;
    }
    ReadOptions options;
    options.Series = dicomObject;
    options.Progress = progress;
    LoadResult read = ReadPath(scene, path, reader, options);
    result.Error = read.Error;
    result.Warnings = read.Warnings;
    result.Nodes = read.Nodes;
    return read.Ok;
  };
}

int RunViewer(int argc, char* argv[], ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& files) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  QApplication::setOrganizationName("RoboPlan");
  QApplication::setApplicationName("roboplan");
  qRPViewerMainWindow window(&manager, scene);
  for (const std::string& file : files) {
    QString error;
    if (!window.LoadFile(QString::fromStdString(file), &error)) {
      std::cerr << "roboplan: " << error.toStdString() << "\n";
    }
  }
  window.resize(1400, 900);
  window.show();
  return QApplication::exec();
}

}  // namespace rp

RP_VIEWER_ENTRY int roboplan_viewer_run(int argc, char* argv[], rp::ModuleManager& manager, vtkRPScene* scene,
                                        const std::vector<std::string>& files) {
  return rp::RunViewer(argc, argv, manager, scene, files);
}

// `roboplan screenshot`'s drawing (rpViewerCommands.cxx parses, loads and reports).
RP_VIEWER_ENTRY bool roboplan_viewer_screenshot(vtkRPScene* scene, const std::string& pngPath,
                                                const rp::ScreenshotOptions& options,
                                                rp::viewer::ScreenshotResult& drawn, std::string& error) {
  // $DISPLAY when it answers, else a private Xvfb for this process (rpXDisplay.h).
  if (!rp::EnsureXDisplay(error)) return false;
  rp::ViewController controller(scene);
  if (!rp::SaveScreenshot(controller, pngPath, options, error)) return false;
  drawn.Layout = options.Layout >= 0 ? options.Layout : controller.GetLayoutNode()->GetViewArrangement();
  controller.GetSlicePointRAS(drawn.SlicePointRAS);
  if (vtkRPScalarVolumeNode* background = controller.GetBackgroundVolume()) drawn.BackgroundID = background->GetID();
  return true;
}
