#pragma once
// Headless rendering of a scene into one PNG: the views of a layout drawn in one offscreen
// render window (the 4-up layout composited as axial | 3D over sagittal | coronal).
#include <string>

class vtkImageData;
class vtkRPScene;

namespace rp {

class ViewController;

struct ScreenshotOptions {
  int Width = 800;
  int Height = 800;
  int Layout = -1;  // vtkRPLayoutNode::Arrangement; −1: the scene's layout node
  bool HasSlicePoint = false;
  double SlicePointRAS[3] = {0, 0, 0};
};

/// Viewport (xmin, ymin, xmax, ymax) of a view in a layout; false when the layout hides it.
bool GetLayoutViewport(int layout, int viewKind, double viewport[4]);

/// Renders the controller's views offscreen into `image` (RGB, width × height). The slice views
/// show their slice nodes as they are; the 3D camera frames the visible models for this size.
bool RenderViews(ViewController& controller, const ScreenshotOptions& options, vtkImageData* image, std::string& error);
/// Renders the scene (with a fresh controller: slices centred on the first volume) to a PNG.
bool SaveScreenshot(vtkRPScene* scene, const std::string& pngPath, const ScreenshotOptions& options, std::string& error);
/// Same with the caller's controller (its view state, e.g. the slice point, is used and kept).
bool SaveScreenshot(ViewController& controller, const std::string& pngPath, const ScreenshotOptions& options,
                    std::string& error);

}  // namespace rp
