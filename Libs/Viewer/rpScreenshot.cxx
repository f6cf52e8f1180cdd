#include "rpScreenshot.h"

#include <cstdlib>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include "rpAtomicFile.h"
#include "rpView.h"
#include "rpViewController.h"
#include "rpXDisplay.h"
#include "vtkRPLayoutNode.h"

namespace rp {

bool GetLayoutViewport(int layout, int viewKind, double viewport[4]) {
  auto set = [viewport](double x0, double y0, double x1, double y1) {
    viewport[0] = x0;
    viewport[1] = y0;
    viewport[2] = x1;
    viewport[3] = y1;
    return true;
  };
  const auto kind = static_cast<ViewKind>(viewKind);
  switch (layout) {
    case vtkRPLayoutNode::FourUp:
      if (kind == ViewKind::Axial) return set(0, 0.5, 0.5, 1);
      if (kind == ViewKind::ThreeD) return set(0.5, 0.5, 1, 1);
      if (kind == ViewKind::Sagittal) return set(0, 0, 0.5, 0.5);
      return set(0.5, 0, 1, 0.5);
    case vtkRPLayoutNode::OneUp3D:
      return kind == ViewKind::ThreeD && set(0, 0, 1, 1);
    case vtkRPLayoutNode::OneUpAxial:
      return kind == ViewKind::Axial && set(0, 0, 1, 1);
    case vtkRPLayoutNode::OneUpSagittal:
      return kind == ViewKind::Sagittal && set(0, 0, 1, 1);
    case vtkRPLayoutNode::OneUpCoronal:
      return kind == ViewKind::Coronal && set(0, 0, 1, 1);
    default:
      return false;
  }
}

bool RenderViews(ViewController& controller, const ScreenshotOptions& options, vtkImageData* image, std::string& error) {
  if (options.Width < 16 || options.Height < 16 || options.Width > 8192 || options.Height > 8192) {
    error = "image size must be between 16 and 8192 pixels a side";
    return false;
  }
  vtkNew<vtkRenderWindow> window;
  if (!PrepareOffscreenWindow(window, error)) return false;
  window->SetMultiSamples(0);  // identical pixels run to run (regression tests compare them)
  window->SetSize(options.Width, options.Height);
  window->SetNumberOfLayers(2);
  const int layout = options.Layout >= 0 ? options.Layout : controller.GetLayoutNode()->GetViewArrangement();
  if (options.HasSlicePoint) controller.SetSlicePointRAS(options.SlicePointRAS);
  for (int kind = 0; kind < 4; ++kind) {
    double viewport[4];
    if (GetLayoutViewport(layout, kind, viewport)) {
      controller.GetView(static_cast<ViewKind>(kind))->AttachToRenderWindow(window, viewport);
    }
  }
  controller.ResetCameras3D();  // with the window's aspect ratio known
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  image->DeepCopy(grab->GetOutput());
  for (int kind = 0; kind < 4; ++kind) controller.GetView(static_cast<ViewKind>(kind))->DetachFromRenderWindow();
  if (image->GetNumberOfPoints() != vtkIdType(options.Width) * options.Height) {
    error = "the offscreen render window returned no image (is there an X display? run under xvfb-run -a)";
    return false;
  }
  return true;
}

bool SaveScreenshot(vtkRPScene* scene, const std::string& pngPath, const ScreenshotOptions& options, std::string& error) {
  ViewController controller(scene);
  return SaveScreenshot(controller, pngPath, options, error);
}

bool SaveScreenshot(ViewController& controller, const std::string& pngPath, const ScreenshotOptions& options,
                    std::string& error) {
  vtkNew<vtkImageData> image;
  if (!RenderViews(controller, options, image, error)) return false;
  return WriteAtomicallyWith(
      pngPath,
      [&image](const std::string& temporary, std::string& writeError) {
        vtkNew<vtkPNGWriter> writer;
        writer->SetFileName(temporary.c_str());
        writer->SetInputData(image);
        writer->Write();
        if (writer->GetErrorCode() != 0) {
          writeError = "PNG writer failed";
          return false;
        }
        return true;
      },
      error);
}

}  // namespace rp
