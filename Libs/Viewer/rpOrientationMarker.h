#pragma once
// The patient-axes marker of the 3D view (Slicer's orientation marker): a small cube labelled
// R/L, A/P, S/I in a corner of the view, turned with the view's camera so it always shows which
// way the patient faces. Drawn by its own renderer on top of the view (works in Qt and offscreen,
// no interactor needed).
#include <vtkNew.h>

class vtkAnnotatedCubeActor;
class vtkCallbackCommand;
class vtkObject;
class vtkRenderWindow;
class vtkRenderer;

namespace rp {

class OrientationMarker {
 public:
  /// Follows `viewRenderer`'s camera; `size` is the marker's share of the view's shorter side.
  explicit OrientationMarker(vtkRenderer* viewRenderer, double size = 0.22);
  ~OrientationMarker();
  OrientationMarker(const OrientationMarker&) = delete;
  OrientationMarker& operator=(const OrientationMarker&) = delete;

  /// Adds the marker to the view's window; the view's viewport is xmin, ymin, xmax, ymax.
  void Attach(vtkRenderWindow* window, const double viewViewport[4]);
  void Detach();
  vtkRenderer* GetRenderer() const { return this->Renderer; }

 private:
  static void OnViewRender(vtkObject*, unsigned long, void* clientData, void*);
  void UpdateCamera();

  vtkRenderer* ViewRenderer;
  vtkRenderWindow* Window = nullptr;
  double Size;
  double ViewViewport[4] = {0, 0, 1, 1};
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkAnnotatedCubeActor> Cube;
  vtkNew<vtkCallbackCommand> Callback;
  unsigned long Tag = 0;
};

}  // namespace rp
