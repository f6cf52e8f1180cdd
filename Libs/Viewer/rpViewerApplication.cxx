#include "rpViewerApplication.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <unistd.h>

#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>
#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpDataLoader.h"
#include "rpModuleManager.h"
#include "rpNodeStorage.h"
#include "rpSceneIO.h"
#include "rpScreenshot.h"
#include "rpViewController.h"
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

bool LoadSceneOrDataFile(vtkRPScene* scene, const std::string& path, std::string& error,
                         std::vector<std::string>* warnings) {
  const LoadResult result = LoadPath(scene, path);
  if (!result.Ok) {
    error = result.Error;
    return false;
  }
  if (warnings) warnings->insert(warnings->end(), result.Warnings.begin(), result.Warnings.end());
  return true;
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

namespace {

bool ParseSize(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  if (x == std::string::npos) return false;
  try {
    size_t used = 0;
    width = std::stoi(text.substr(0, x), &used);
    if (used != x) return false;
    const std::string rest = text.substr(x + 1);
    height = std::stoi(rest, &used);
    return used == rest.size();
  } catch (...) {
    return false;
  }
}

int RunScreenshot(CommandContext& context) {
  std::ostream& out = *context.Out;  // the host's streams (a test may capture them)
  std::ostream& err = *context.Err;
  ArgParser parser("screenshot", "Render a scene headless (offscreen) into one PNG: the views of a layout.");
  parser.Positional("files", "scene (*.rpscene, Slicer's *.mrml, *.mrb), data files or DICOM series folders to load", true, true)
      .Option("out", "png", "output PNG file")
      .Option("layout", "name", "4up | 3d | axial | sagittal | coronal (default: the scene's, else 4up)")
      .Option("size", "WxH", "image size in pixels", std::string("800x800"))
      .Option("slice-point", "R,A,S", "where the slices cut (default: centre of the first volume)");
  if (const auto exitCode = parser.ParseCommand(context.Arguments, out, err)) return *exitCode;
  ScreenshotOptions options;
  if (!parser.Has("out")) {
    err << "roboplan screenshot: --out is required\n" << parser.Usage();
    return 2;
  }
  if (parser.Has("layout")) options.Layout = vtkRPLayoutNode::GetArrangementFromString(parser.Get("layout"));
  if (parser.Has("layout") && options.Layout < 0) {
    err << "roboplan screenshot: unknown layout '" << parser.Get("layout") << "' (4up, 3d, axial, sagittal, coronal)\n";
    return 2;
  }
  if (!ParseSize(parser.Get("size"), options.Width, options.Height) || options.Width < 16 || options.Height < 16 ||
      options.Width > 8192 || options.Height > 8192) {
    err << "roboplan screenshot: --size must be WxH with 16..8192 pixels, got '" << parser.Get("size") << "'\n";
    return 2;
  }
  if (parser.Has("slice-point")) {
    try {
      std::vector<double> point = parser.GetDoubles("slice-point", 3);
      options.HasSlicePoint = true;
      for (int i = 0; i < 3; ++i) options.SlicePointRAS[i] = point[static_cast<size_t>(i)];
    } catch (const std::exception& e) {
      err << "roboplan screenshot: " << e.what() << "\n";
      return 2;
    }
  }
  vtkRPScene* scene = context.Scene;
  for (const std::string& file : parser.GetAll("files")) {
    std::string error;
    std::vector<std::string> warnings;
    if (!LoadSceneOrDataFile(scene, file, error, &warnings)) {
      err << "roboplan screenshot: " << error << "\n";
      return 1;
    }
    for (const std::string& warning : warnings) err << "roboplan screenshot: warning: " << warning << "\n";
  }
  std::string error;
  // $DISPLAY when it answers, else a private Xvfb for this process (rpXDisplay.h).
  if (!EnsureXDisplay(error)) {
    err << "roboplan screenshot: " << error << "\n";
    return 1;
  }
  ViewController controller(scene);
  if (!SaveScreenshot(controller, parser.Get("out"), options, error)) {
    err << "roboplan screenshot: " << error << "\n";
    return 1;
  }
  const int layout = options.Layout >= 0 ? options.Layout : controller.GetLayoutNode()->GetViewArrangement();
  if (parser.Json()) {
    nlohmann::json doc = {{"out", parser.Get("out")}, {"width", options.Width}, {"height", options.Height},
                          {"layout", vtkRPLayoutNode::GetArrangementAsString(layout)}, {"nodes", scene->GetNumberOfNodes()}};
    double point[3];
    controller.GetSlicePointRAS(point);
    doc["slicePointRAS"] = {point[0], point[1], point[2]};
    if (vtkRPScalarVolumeNode* background = controller.GetBackgroundVolume()) {
      double bounds[6];
      background->GetRASBounds(bounds);
      doc["background"] = {{"name", background->GetName()}, {"rasBounds", bounds},
                           {"window", background->GetWindow()}, {"level", background->GetLevel()}};
    }
    out << doc.dump(2) << "\n";
  } else {
    err << "wrote " << parser.Get("out") << " (" << options.Width << "x" << options.Height << ", "
              << vtkRPLayoutNode::GetArrangementAsString(layout) << ")\n";
  }
  return 0;
}

}  // namespace

std::vector<rp::Command> ViewerCommands() {
  return {{"screenshot", "render scene/data files headless into a PNG (4up, 3d or one slice view)", &RunScreenshot}};
}

}  // namespace rp
