#include "vtkRPSliceInteractorStyle.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include "rpView.h"
#include "rpViewController.h"

vtkStandardNewMacro(vtkRPSliceInteractorStyle);
vtkStandardNewMacro(vtkRPThreeDInteractorStyle);

namespace {
constexpr int ClickTolerance = 3;  // pixels a press may move and still count as a click
constexpr double FiducialGrabPixels = 6.0;  // a press this close to a fiducial grabs it
}

void vtkRPSliceInteractorStyle::OnLeftButtonDown() {
  if (!this->Controller || !this->Interactor) return;
  this->Interactor->GetEventPosition(this->Press);
  this->Last[0] = this->Press[0];
  this->Last[1] = this->Press[1];
  this->Current = this->Interactor->GetShiftKey() ? Panning : LeftPending;
  // Pressing on a fiducial grabs it (dragging moves it; a click leaves it where it is).
  if (this->Current == LeftPending &&
      this->Controller->FindFiducialAt(this->Kind, this->Press[0], this->Press[1], FiducialGrabPixels, this->FiducialListID,
                                       this->FiducialIndex)) {
    this->Current = MovingFiducial;
  }
  this->GrabFocus(this->EventCallbackCommand);
}

void vtkRPSliceInteractorStyle::OnLeftButtonUp() {
  if (this->Current == LeftPending && this->Controller) {
    this->Controller->ClickInSliceView(this->Kind, this->Press[0], this->Press[1]);
  }
  this->Finish();
}

void vtkRPSliceInteractorStyle::OnMiddleButtonDown() {
  if (!this->Interactor) return;
  this->Interactor->GetEventPosition(this->Last);
  this->Current = Panning;
  this->GrabFocus(this->EventCallbackCommand);
}

void vtkRPSliceInteractorStyle::OnMiddleButtonUp() { this->Finish(); }

void vtkRPSliceInteractorStyle::OnRightButtonDown() {
  if (!this->Interactor) return;
  this->Interactor->GetEventPosition(this->Last);
  this->Current = Zooming;
  this->GrabFocus(this->EventCallbackCommand);
}

void vtkRPSliceInteractorStyle::OnRightButtonUp() { this->Finish(); }

void vtkRPSliceInteractorStyle::Finish() {
  this->Current = None;
  if (this->Interactor) this->ReleaseFocus();
}

void vtkRPSliceInteractorStyle::OnMouseMove() {
  if (!this->Controller || !this->Interactor || this->Current == None) return;
  int position[2];
  this->Interactor->GetEventPosition(position);
  const int dx = position[0] - this->Last[0], dy = position[1] - this->Last[1];
  rp::View* view = this->Controller->GetView(this->Kind);
  switch (this->Current) {
    case LeftPending:
      if (std::abs(position[0] - this->Press[0]) <= ClickTolerance && std::abs(position[1] - this->Press[1]) <= ClickTolerance) {
        return;  // still a click
      }
      this->Current = WindowLevel;
      [[fallthrough]];
    case WindowLevel:
      this->Controller->AdjustWindowLevel(dx, dy);
      break;
    case Panning: {
      double from[3], to[3];
      if (view->DisplayToRAS(this->Last[0], this->Last[1], from) && view->DisplayToRAS(position[0], position[1], to)) {
        const double delta[3] = {from[0] - to[0], from[1] - to[1], from[2] - to[2]};
        view->Pan(delta);
      }
      break;
    }
    case Zooming:
      view->Zoom(std::pow(1.01, dy));
      break;
    case MovingFiducial: {
      double ras[3];
      if (view->DisplayToRAS(position[0], position[1], ras)) this->Controller->MoveFiducial(this->FiducialListID, this->FiducialIndex, ras);
      break;
    }
    default:
      break;
  }
  this->Last[0] = position[0];
  this->Last[1] = position[1];
  view->RequestRender();
}

void vtkRPSliceInteractorStyle::Wheel(int steps) {
  if (!this->Controller || !this->Interactor) return;
  if (this->Interactor->GetControlKey()) {
    this->Controller->GetView(this->Kind)->Zoom(steps > 0 ? 1.1 : 1.0 / 1.1);
  } else {
    this->Controller->MoveSlice(this->Kind, steps);
  }
}

void vtkRPSliceInteractorStyle::OnMouseWheelForward() { this->Wheel(1); }
void vtkRPSliceInteractorStyle::OnMouseWheelBackward() { this->Wheel(-1); }

void vtkRPSliceInteractorStyle::OnKeyPress() {
  if (!this->Controller || !this->Interactor) return;
  const std::string key = this->Interactor->GetKeySym() ? this->Interactor->GetKeySym() : "";
  if (key == "Up" || key == "Prior") {
    this->Controller->MoveSlice(this->Kind, 1);
  } else if (key == "Down" || key == "Next") {
    this->Controller->MoveSlice(this->Kind, -1);
  } else if (key == "plus" || key == "equal" || key == "KP_Add") {
    this->Controller->GetView(this->Kind)->Zoom(1.2);
  } else if (key == "minus" || key == "KP_Subtract") {
    this->Controller->GetView(this->Kind)->Zoom(1.0 / 1.2);
  } else if (key == "r" || key == "R") {
    this->Controller->GetView(this->Kind)->ResetCamera();
  } else if (key == "1") {
    this->Controller->ApplyWindowLevelPreset(rp::WindowLevelPreset::CTBone);
  } else if (key == "2") {
    this->Controller->ApplyWindowLevelPreset(rp::WindowLevelPreset::CTSoftTissue);
  } else if (key == "3") {
    this->Controller->ApplyWindowLevelPreset(rp::WindowLevelPreset::MR);
  }
}

void vtkRPThreeDInteractorStyle::OnChar() {
  if (!this->Interactor || !this->Controller) return;
  const char key = this->Interactor->GetKeyCode();
  rp::View* view = this->Controller->GetView(rp::ViewKind::ThreeD);
  if (key == 'r' || key == 'R') {
    view->ResetCamera();
  } else if (key == '+' || key == '=') {
    view->Zoom(1.2);
  } else if (key == '-') {
    view->Zoom(1.0 / 1.2);
  }
  view->RequestRender();
}

void vtkRPThreeDInteractorStyle::OnKeyPress() {
  if (!this->Interactor || !this->Controller) return;
  const std::string key = this->Interactor->GetKeySym() ? this->Interactor->GetKeySym() : "";
  rp::View* view = this->Controller->GetView(rp::ViewKind::ThreeD);
  vtkCamera* camera = view->GetRenderer()->GetActiveCamera();
  // Arrow keys rotate the camera around the focal point by 5 degrees.
  if (key == "Left") camera->Azimuth(-5);
  else if (key == "Right") camera->Azimuth(5);
  else if (key == "Up") camera->Elevation(5);
  else if (key == "Down") camera->Elevation(-5);
  else return;
  camera->OrthogonalizeViewUp();
  view->GetRenderer()->ResetCameraClippingRange();
  view->RequestRender();
}

void vtkRPThreeDInteractorStyle::OnLeftButtonDown() {
  if (this->Interactor) this->Interactor->GetEventPosition(this->Press);
  // Pressing on a control point (a fiducial, a trajectory's entry or target) grabs it.
  this->Dragging = this->Controller && this->Controller->FindControlPointIn3D(this->Press[0], this->Press[1], FiducialGrabPixels,
                                                                           this->DraggedNodeID, this->DraggedIndex);
  if (this->Dragging) {
    this->GrabFocus(this->EventCallbackCommand);
    return;
  }
  this->Superclass::OnLeftButtonDown();
}

void vtkRPThreeDInteractorStyle::OnMouseMove() {
  if (!this->Dragging || !this->Interactor || !this->Controller) {
    this->Superclass::OnMouseMove();
    return;
  }
  int position[2];
  this->Interactor->GetEventPosition(position);
  this->Controller->DragControlPointIn3D(this->DraggedNodeID, this->DraggedIndex, position[0], position[1]);
}

void vtkRPThreeDInteractorStyle::OnLeftButtonUp() {
  if (this->Dragging) {
    this->Dragging = false;
    this->ReleaseFocus();
    return;
  }
  this->Superclass::OnLeftButtonUp();
  if (!this->Interactor || !this->Controller) return;
  int position[2];
  this->Interactor->GetEventPosition(position);
  if (std::abs(position[0] - this->Press[0]) <= ClickTolerance && std::abs(position[1] - this->Press[1]) <= ClickTolerance) {
    this->Controller->ClickIn3DView(this->Press[0], this->Press[1]);
  }
}
