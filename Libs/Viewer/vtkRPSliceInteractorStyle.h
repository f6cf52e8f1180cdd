#ifndef vtkRPSliceInteractorStyle_h
#define vtkRPSliceInteractorStyle_h
// Mouse and keys in a slice view (and the 3D view's keys):
//   left click            set the slice point (other views follow) / place a fiducial
//   left drag on a fiducial   move it (any control point: a trajectory's entry or target too)
//   left drag             window/level (right = wider window, up = higher level)
//   wheel, Up/Down, PgUp/PgDn   move the slice by one step
//   right drag, Ctrl+wheel      zoom;   middle drag, Shift+left drag   pan
//   +/-                   zoom in/out
//   r                     reset the view;  1/2/3  CT bone / CT soft tissue / MR presets
// 3D view: trackball mouse; arrow keys rotate 5°, +/- zoom, r resets; click places a fiducial
// on a model or slice in "place fiducials" mode; a drag from a control point moves it.
#include <string>

#include <vtkInteractorStyle.h>
#include <vtkInteractorStyleTrackballCamera.h>

#include "rpSliceGeometry.h"

namespace rp {
class ViewController;
}

class vtkRPSliceInteractorStyle : public vtkInteractorStyle {
 public:
  static vtkRPSliceInteractorStyle* New();
  vtkTypeMacro(vtkRPSliceInteractorStyle, vtkInteractorStyle);

  void SetController(rp::ViewController* controller, rp::ViewKind kind) {
    this->Controller = controller;
    this->Kind = kind;
  }

  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;
  void OnMiddleButtonDown() override;
  void OnMiddleButtonUp() override;
  void OnRightButtonDown() override;
  void OnRightButtonUp() override;
  void OnMouseMove() override;
  void OnMouseWheelForward() override;
  void OnMouseWheelBackward() override;
  void OnKeyPress() override;
  void OnChar() override {}  // no VTK default keys (e.g. 'e'/'q' would exit the application)

 protected:
  vtkRPSliceInteractorStyle() = default;
  ~vtkRPSliceInteractorStyle() override = default;

 private:
  vtkRPSliceInteractorStyle(const vtkRPSliceInteractorStyle&) = delete;
  void operator=(const vtkRPSliceInteractorStyle&) = delete;
  enum Action { None, LeftPending, WindowLevel, Panning, Zooming, MovingFiducial };
  void Wheel(int steps);
  void Finish();

  rp::ViewController* Controller = nullptr;
  rp::ViewKind Kind = rp::ViewKind::Axial;
  Action Current = None;
  int Press[2] = {0, 0};
  int Last[2] = {0, 0};
  std::string FiducialListID;  // the point being dragged
  int FiducialIndex = -1;
};

/// 3D view: trackball camera; arrows rotate, +/- zoom, 'r' resets; VTK's default keys are off.
class vtkRPThreeDInteractorStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static vtkRPThreeDInteractorStyle* New();
  vtkTypeMacro(vtkRPThreeDInteractorStyle, vtkInteractorStyleTrackballCamera);
  void SetController(rp::ViewController* controller) { this->Controller = controller; }
  void OnChar() override;
  void OnKeyPress() override;
  /// In "place fiducials" mode a click (no drag) places a point on the model or slice under it;
  /// a press on a control point drags it over the models and slices.
  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;
  void OnMouseMove() override;

 protected:
  vtkRPThreeDInteractorStyle() = default;
  ~vtkRPThreeDInteractorStyle() override = default;

 private:
  vtkRPThreeDInteractorStyle(const vtkRPThreeDInteractorStyle&) = delete;
  void operator=(const vtkRPThreeDInteractorStyle&) = delete;
  rp::ViewController* Controller = nullptr;
  int Press[2] = {0, 0};
  bool Dragging = false;
  std::string DraggedNodeID;
  int DraggedIndex = -1;
};

#endif
