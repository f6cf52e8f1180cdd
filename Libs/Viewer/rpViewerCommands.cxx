#include "rpViewerCommands.h"

#include <optional>
#include <ostream>

#include <nlohmann/json.hpp>

#include "rpArgParser.h"
#include "rpDataLoader.h"
#include "rpSiblingLibrary.h"
#include "rpViewerEntries.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace rp {

namespace {

/// The entry `symbol` of libRoboPlanViewer.so (beside this library), loaded on first use; nullptr
/// with `error` naming the library's path and why.
template <typename Function>
Function ViewerEntry(const char* symbol, std::string& error) {
  return SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&ViewerEntry<Function>), viewer::Library,
                                          symbol, error);
}

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

// The options of `roboplan screenshot` into `options`; the exit code when the command ends here
// (--help, bad arguments).
std::optional<int> ParseScreenshot(ArgParser& parser, const std::vector<std::string>& arguments,
                                   ScreenshotOptions& options, std::ostream& out, std::ostream& err) {
  parser.Positional("files", "scene (*.rpscene, Slicer's *.mrml, *.mrb), data files or DICOM series folders to load", true, true)
      .Option("out", "png", "output PNG file")
      .Option("layout", "name", "4up | 3d | axial | sagittal | coronal (default: the scene's, else 4up)")
      .Option("size", "WxH", "image size in pixels", std::string("800x800"))
      .Option("slice-point", "R,A,S", "where the slices cut (default: centre of the first volume)");
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return exitCode;
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
  return std::nullopt;
}

void ReportScreenshot(const ArgParser& parser, vtkRPScene* scene, const ScreenshotOptions& options,
                      const viewer::ScreenshotResult& drawn, std::ostream& out, std::ostream& err) {
  if (!parser.Json()) {
    err << "wrote " << parser.Get("out") << " (" << options.Width << "x" << options.Height << ", "
        << vtkRPLayoutNode::GetArrangementAsString(drawn.Layout) << ")\n";
    return;
  }
  nlohmann::json doc = {{"out", parser.Get("out")}, {"width", options.Width}, {"height", options.Height},
                        {"layout", vtkRPLayoutNode::GetArrangementAsString(drawn.Layout)},
                        {"nodes", scene->GetNumberOfNodes()}};
  doc["slicePointRAS"] = {drawn.SlicePointRAS[0], drawn.SlicePointRAS[1], drawn.SlicePointRAS[2]};
  if (auto* background = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodeByID(drawn.BackgroundID))) {
    double bounds[6];
    background->GetRASBounds(bounds);
    doc["background"] = {{"name", background->GetName()}, {"rasBounds", bounds},
                         {"window", background->GetWindow()}, {"level", background->GetLevel()}};
  }
  out << doc.dump(2) << "\n";
}

// Parse → load the files → draw (libRoboPlanViewer.so) → report.
int RunScreenshot(CommandContext& context) {
  std::ostream& out = *context.Out;  // the host's streams (a test may capture them)
  std::ostream& err = *context.Err;
  ArgParser parser("screenshot", "Render a scene headless (offscreen) into one PNG: the views of a layout.");
  ScreenshotOptions options;
  if (const auto exitCode = ParseScreenshot(parser, context.Arguments, options, out, err)) return *exitCode;
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
  viewer::ScreenshotResult drawn;
  const auto draw = ViewerEntry<viewer::ScreenshotFunction>("roboplan_viewer_screenshot", error);
  if (!draw || !draw(scene, parser.Get("out"), options, drawn, error)) {
    err << "roboplan screenshot: " << error << "\n";
    return 1;
  }
  ReportScreenshot(parser, scene, options, drawn, out, err);
  return 0;
}

}  // namespace

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

int LaunchViewer(int argc, char* argv[], ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& files,
                 std::ostream& err) {
  std::string error;
  const auto run = ViewerEntry<viewer::RunFunction>("roboplan_viewer_run", error);
  if (!run) {
    err << "roboplan: the viewer cannot be opened: " << error << "\n";
    return 1;
  }
  return run(argc, argv, manager, scene, files);
}

std::vector<rp::Command> ViewerCommands() {
  return {{"screenshot", "render scene/data files headless into a PNG (4up, 3d or one slice view)", &RunScreenshot}};
}

}  // namespace rp
