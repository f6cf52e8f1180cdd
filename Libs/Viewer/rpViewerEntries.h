#pragma once
// The entries of libRoboPlanViewer.so (rpViewerApplication.cxx) that the light side of the viewer
// (rpViewerCommands.cxx: the Viewer module's `screenshot` and the viewer's start) resolves when it
// opens a window or renders (rp::SiblingLibraryFunction): their names and types, in one place for
// both sides. Nothing here includes Qt or VTK's rendering.
#include <string>
#include <vector>

#include "rpScreenshot.h"

class vtkRPScene;

#define RP_VIEWER_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp {
class ModuleManager;
}

namespace rp::viewer {

constexpr const char* Library = "libRoboPlanViewer.so";

/// What `roboplan screenshot` reports of the views it drew (the view state the controller chose).
struct ScreenshotResult {
  int Layout = -1;                     // vtkRPLayoutNode::Arrangement drawn
  double SlicePointRAS[3] = {0, 0, 0};
  std::string BackgroundID;            // the slice views' background volume; "" when none
};

/// roboplan_viewer_run: the Qt main window (rp::RunViewer).
using RunFunction = int (*)(int, char**, rp::ModuleManager&, vtkRPScene*, const std::vector<std::string>&);
/// roboplan_viewer_screenshot: an X display (rpXDisplay.h), then the scene's views into a PNG.
using ScreenshotFunction = bool (*)(vtkRPScene*, const std::string&, const rp::ScreenshotOptions&, ScreenshotResult&,
                                    std::string&);

}  // namespace rp::viewer
