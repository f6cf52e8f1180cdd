#pragma once
// One view (axial, sagittal, coronal or 3D): its renderers, its displayable managers and its
// camera. A view renders into any render window at a viewport, so the same code draws in a Qt
// widget and in an offscreen window for screenshots. Slice views have two layers: the image
// (layer 0) and overlays (layer 1: outlines, fiducials, tools, crosshair) drawn on top.
// Displayable managers ask for a render; the host renders views whose NeedsRender() is true.
#include <functional>
#include <vector>

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpSliceGeometry.h"

class vtkActor;
class vtkObject;
class vtkCallbackCommand;
class vtkLineSource;
class vtkRenderWindow;
class vtkRenderer;
class vtkRPDisplayableManager;
class vtkRPScene;
class vtkRPViewState;
class vtkTextActor;

namespace rp {

class View {
 public:
  View(ViewKind kind, vtkRPScene* scene, vtkRPViewState* state);
  ~View();
  View(const View&) = delete;
  View& operator=(const View&) = delete;

  ViewKind GetKind() const { return this->Kind; }
  bool IsSlice() const { return IsSliceView(this->Kind); }
  vtkRPScene* GetScene() const { return this->Scene; }
  vtkRPViewState* GetViewState() const { return this->State; }

  /// Layer 0 (images in slice views; everything in 3D).
  vtkRenderer* GetRenderer() const { return this->Renderer; }
  /// Where overlays go: layer 1 in slice views, the main renderer in 3D (depth-tested there).
  vtkRenderer* GetOverlayRenderer() const;

  /// Adds the view's renderers to a window at a viewport (xmin, ymin, xmax, ymax in 0..1).
  void AttachToRenderWindow(vtkRenderWindow* window, const double viewport[4]);
  void DetachFromRenderWindow();
  vtkRenderWindow* GetRenderWindow() const { return this->Window; }

  void RequestRender();
  bool NeedsRender() const { return this->RenderRequested; }
  /// Clears the flag (the host calls this when it renders the window).
  void MarkRendered() { this->RenderRequested = false; }
  /// Called on every RequestRender (e.g. to wake a host); optional.
  void SetRenderRequestCallback(std::function<void()> callback) { this->OnRenderRequest = std::move(callback); }

  /// Slice views: fit the background volume (or a 250 mm field) around the slice point.
  /// 3D: fit everything visible, seen from the front (a little from the right and above), head up.
  void ResetCamera();
  /// Slice views: the RAS point on the slice plane under a display pixel (VTK display
  /// coordinates: origin bottom-left of the window). False for 3D or when outside the viewport.
  bool DisplayToRAS(double x, double y, double ras[3]) const;
  /// Inverse: display pixel of a RAS point.
  void RASToDisplay(const double ras[3], double display[2]) const;
  /// Slice views: distance along the normal of one scroll step (the background's spacing or 1 mm).
  double GetSliceStep() const;
  /// Slice views: the slice offset along the normal (mm).
  double GetSliceOffset() const;
  /// Slice views: zoom by a factor (> 1 magnifies) and pan by a RAS offset in the plane.
  void Zoom(double factor);
  void Pan(const double deltaRAS[3]);

  /// Displayable managers created for this view kind (volume slices, models, outlines, fiducials, tools).
  const std::vector<vtkSmartPointer<vtkRPDisplayableManager>>& GetDisplayableManagers() const {
    return this->Managers;
  }
  template <class T>
  T* GetDisplayableManager() const {
    for (const auto& manager : this->Managers) {
      if (T* typed = T::SafeDownCast(manager)) return typed;
    }
    return nullptr;
  }

 private:
  static void OnViewStateModified(vtkObject*, unsigned long, void* clientData, void*);
  void UpdateSliceCamera();
  void UpdateCrosshair();
  void UpdateCornerText();

  ViewKind Kind;
  vtkRPScene* Scene;
  vtkRPViewState* State;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderer> Overlay;
  vtkRenderWindow* Window = nullptr;
  std::vector<vtkSmartPointer<vtkRPDisplayableManager>> Managers;
  vtkNew<vtkCallbackCommand> StateCallback;
  unsigned long StateTag = 0;
  vtkNew<vtkLineSource> CrossLines[2];
  vtkNew<vtkActor> CrossActors[2];
  vtkNew<vtkTextActor> CornerText;
  bool RenderRequested = true;
  bool CameraInitialized = false;
  std::function<void()> OnRenderRequest;
};

}  // namespace rp
