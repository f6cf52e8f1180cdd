#include "rpView.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCoordinate.h>
#include <vtkLineSource.h>
#include <vtkMath.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "vtkRPFiducialDisplayableManager.h"
#include "vtkRPModelDisplayableManager.h"
#include "vtkRPModelSliceDisplayableManager.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationSliceDisplayableManager.h"
#include "vtkRPToolDisplayableManager.h"
#include "vtkRPViewState.h"
#include "vtkRPVolumeSliceDisplayableManager.h"

namespace rp {

namespace {
// Slice cameras sit this far from the plane; overlays up to this far on either side are drawn.
constexpr double SliceCameraDistance = 2000.0;
constexpr double DefaultFieldOfView = 250.0;  // mm, when there is no volume
}  // namespace

View::View(ViewKind kind, vtkRPScene* scene, vtkRPViewState* state) : Kind(kind), Scene(scene), State(state) {
  this->Renderer->SetLayer(0);
  this->Overlay->SetLayer(1);
  this->Overlay->InteractiveOff();
  this->Overlay->SetActiveCamera(this->Renderer->GetActiveCamera());
  if (this->IsSlice()) {
    this->Renderer->SetBackground(0, 0, 0);
    this->Renderer->GetActiveCamera()->ParallelProjectionOn();
    this->Managers.push_back(vtkSmartPointer<vtkRPVolumeSliceDisplayableManager>::New());
    this->Managers.push_back(vtkSmartPointer<vtkRPSegmentationSliceDisplayableManager>::New());
    this->Managers.push_back(vtkSmartPointer<vtkRPModelSliceDisplayableManager>::New());
  } else {
    this->Renderer->SetBackground(0.76, 0.76, 0.90);
    this->Renderer->SetBackground2(0.45, 0.45, 0.62);
    this->Renderer->GradientBackgroundOn();
    this->Managers.push_back(vtkSmartPointer<vtkRPVolumeSliceDisplayableManager>::New());
    this->Managers.push_back(vtkSmartPointer<vtkRPModelDisplayableManager>::New());
  }
  this->Managers.push_back(vtkSmartPointer<vtkRPFiducialDisplayableManager>::New());
  this->Managers.push_back(vtkSmartPointer<vtkRPToolDisplayableManager>::New());

  // Crosshair: the lines where the two other slice planes cut this one, in their colours.
  if (this->IsSlice()) {
    const SliceAxes axes = GetSliceAxes(kind);
    for (int i = 0; i < 2; ++i) {
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(this->CrossLines[i]->GetOutputPort());
      this->CrossActors[i]->SetMapper(mapper);
      this->CrossActors[i]->PickableOff();
      // Line i runs along X (i = 0) or Y (i = 1); it lies in the plane whose normal is the other axis.
      const double* other = i == 0 ? axes.Y : axes.X;
      ViewKind otherKind = std::fabs(other[0]) > 0.5 ? ViewKind::Sagittal
                           : std::fabs(other[1]) > 0.5 ? ViewKind::Coronal : ViewKind::Axial;
      double color[3];
      GetViewColor(otherKind, color);
      this->CrossActors[i]->GetProperty()->SetColor(color);
      this->CrossActors[i]->GetProperty()->SetLineWidth(1.0);
      this->CrossActors[i]->GetProperty()->SetOpacity(0.8);
      this->CrossActors[i]->GetProperty()->LightingOff();
      this->Overlay->AddActor(this->CrossActors[i]);
    }
  }
  this->CornerText->GetTextProperty()->SetFontSize(14);
  double color[3];
  GetViewColor(kind, color);
  this->CornerText->GetTextProperty()->SetColor(color);
  // Relative to the view's viewport (several views may share one window).
  this->CornerText->GetPositionCoordinate()->SetCoordinateSystemToViewport();
  this->CornerText->GetPositionCoordinate()->SetValue(6, 6);
  (this->IsSlice() ? this->Overlay.GetPointer() : this->Renderer.GetPointer())->AddActor2D(this->CornerText);

  for (auto& manager : this->Managers) manager->Initialize(this);

  this->StateCallback->SetClientData(this);
  this->StateCallback->SetCallback(&View::OnViewStateModified);
  this->StateTag = state->AddObserver(vtkCommand::ModifiedEvent, this->StateCallback);
  this->ResetCamera();
  this->UpdateCrosshair();
  this->UpdateCornerText();
}

View::~View() {
  this->State->RemoveObserver(this->StateTag);
  for (auto& manager : this->Managers) manager->Finalize();
  this->DetachFromRenderWindow();
}

vtkRenderer* View::GetOverlayRenderer() const {
  return this->IsSlice() ? this->Overlay.GetPointer() : this->Renderer.GetPointer();
}

void View::AttachToRenderWindow(vtkRenderWindow* window, const double viewport[4]) {
  this->DetachFromRenderWindow();
  this->Window = window;
  window->SetNumberOfLayers(std::max(2, window->GetNumberOfLayers()));
  this->Renderer->SetViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  this->Overlay->SetViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  window->AddRenderer(this->Renderer);
  if (this->IsSlice()) window->AddRenderer(this->Overlay);
  this->RequestRender();
}

void View::DetachFromRenderWindow() {
  if (!this->Window) return;
  this->Window->RemoveRenderer(this->Renderer);
  this->Window->RemoveRenderer(this->Overlay);
  this->Window = nullptr;
}

void View::RequestRender() {
  this->RenderRequested = true;
  if (this->OnRenderRequest) this->OnRenderRequest();
}

void View::OnViewStateModified(vtkObject*, unsigned long, void* clientData, void*) {
  auto* self = static_cast<View*>(clientData);
  if (self->IsSlice()) self->UpdateSliceCamera();
  self->UpdateCrosshair();
  self->UpdateCornerText();
  self->RequestRender();
}

double View::GetSliceStep() const {
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->State->GetBackgroundVolumeID()));
  if (!volume || !volume->GetImageData()) return 1.0;
  double spacing[3];
  volume->GetSpacing(spacing);
  return std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
}

double View::GetSliceOffset() const {
  if (!this->IsSlice()) return 0.0;
  const SliceAxes axes = GetSliceAxes(this->Kind);
  return vtkMath::Dot(axes.Normal, this->State->GetSlicePointRAS());
}

// Keeps the focal point on the slice plane (the pan in the plane is the user's).
void View::UpdateSliceCamera() {
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  const SliceAxes axes = GetSliceAxes(this->Kind);
  double toCamera[3];
  GetCameraDirection(this->Kind, toCamera);
  double focal[3];
  camera->GetFocalPoint(focal);
  const double* point = this->State->GetSlicePointRAS();
  const double shift = vtkMath::Dot(axes.Normal, point) - vtkMath::Dot(axes.Normal, focal);
  for (int i = 0; i < 3; ++i) focal[i] += shift * axes.Normal[i];
  camera->SetFocalPoint(focal);
  camera->SetPosition(focal[0] + SliceCameraDistance * toCamera[0], focal[1] + SliceCameraDistance * toCamera[1],
                      focal[2] + SliceCameraDistance * toCamera[2]);
  camera->SetViewUp(axes.Y);
  camera->SetClippingRange(1.0, 2.0 * SliceCameraDistance);
}

void View::UpdateCrosshair() {
  if (!this->IsSlice()) return;
  const SliceAxes axes = GetSliceAxes(this->Kind);
  const double* p = this->State->GetSlicePointRAS();
  const double halfLength = 5000.0;
  for (int i = 0; i < 2; ++i) {
    const double* dir = i == 0 ? axes.X : axes.Y;
    this->CrossLines[i]->SetPoint1(p[0] - halfLength * dir[0], p[1] - halfLength * dir[1], p[2] - halfLength * dir[2]);
    this->CrossLines[i]->SetPoint2(p[0] + halfLength * dir[0], p[1] + halfLength * dir[1], p[2] + halfLength * dir[2]);
  }
}

void View::UpdateCornerText() {
  char text[96];
  if (this->IsSlice()) {
    static const char* const positive[3] = {"R", "A", "S"};
    static const char* const negative[3] = {"L", "P", "I"};
    const SliceAxes axes = GetSliceAxes(this->Kind);
    const double offset = this->GetSliceOffset();
    std::snprintf(text, sizeof(text), "%s  %s %.1f mm", GetViewName(this->Kind),
                  offset >= 0 ? positive[axes.NormalAxis] : negative[axes.NormalAxis], std::fabs(offset));
  } else {
    std::snprintf(text, sizeof(text), "3D");
  }
  this->CornerText->SetInput(text);
}

void View::ResetCamera() {
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->State->GetBackgroundVolumeID()));
  double bounds[6] = {-0.5 * DefaultFieldOfView, 0.5 * DefaultFieldOfView, -0.5 * DefaultFieldOfView,
                      0.5 * DefaultFieldOfView, -0.5 * DefaultFieldOfView, 0.5 * DefaultFieldOfView};
  if (volume && volume->GetImageData()) volume->GetRASBounds(bounds);

  if (this->IsSlice()) {
    const SliceAxes axes = GetSliceAxes(this->Kind);
    const double center[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
    const double size[3] = {bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]};
    const double width = std::fabs(vtkMath::Dot(size, axes.X)), height = std::fabs(vtkMath::Dot(size, axes.Y));
    double aspect = 1.0;
    if (this->Window) {
      const int* windowSize = this->Window->GetSize();
      double vp[4];
      this->Renderer->GetViewport(vp);
      const double w = windowSize[0] * (vp[2] - vp[0]), h = windowSize[1] * (vp[3] - vp[1]);
      if (w > 0 && h > 0) aspect = w / h;
    }
    camera->SetFocalPoint(center);
    camera->SetParallelScale(1.05 * std::max(0.5 * height, 0.5 * width / aspect));
    this->CameraInitialized = true;
    this->UpdateSliceCamera();
  } else {
    // Seen from the front (slightly oblique), head up.
    this->Renderer->ResetCamera();  // sets a distance that fits what is visible
    double visible[6];
    this->Renderer->ComputeVisiblePropBounds(visible);
    if (!vtkMath::AreBoundsInitialized(visible)) std::copy(bounds, bounds + 6, visible);
    const double center[3] = {0.5 * (visible[0] + visible[1]), 0.5 * (visible[2] + visible[3]), 0.5 * (visible[4] + visible[5])};
    const double radius = 0.5 * std::sqrt((visible[1] - visible[0]) * (visible[1] - visible[0]) +
                                          (visible[3] - visible[2]) * (visible[3] - visible[2]) +
                                          (visible[5] - visible[4]) * (visible[5] - visible[4]));
    const double distance = std::max(1.0, radius) / std::sin(vtkMath::RadiansFromDegrees(camera->GetViewAngle()) * 0.5);
    camera->SetFocalPoint(center);
    camera->SetPosition(center[0], center[1] + distance, center[2]);
    camera->SetViewUp(0, 0, 1);
    // A little from the patient's right and above, so all three slices and the models show.
    camera->Azimuth(-30);
    camera->Elevation(20);
    camera->OrthogonalizeViewUp();
    this->Renderer->ResetCameraClippingRange();
  }
  this->RequestRender();
}

bool View::DisplayToRAS(double x, double y, double ras[3]) const {
  if (!this->IsSlice()) return false;
  vtkRenderer* renderer = this->Renderer;
  renderer->SetDisplayPoint(x, y, 0.5);
  renderer->DisplayToWorld();
  double world[4];
  renderer->GetWorldPoint(world);
  if (world[3] == 0.0) return false;
  for (int i = 0; i < 3; ++i) world[i] /= world[3];
  // Project onto the slice plane along its normal (parallel projection: the view direction).
  const SliceAxes axes = GetSliceAxes(this->Kind);
  const double* p = this->State->GetSlicePointRAS();
  const double d = (world[0] - p[0]) * axes.Normal[0] + (world[1] - p[1]) * axes.Normal[1] + (world[2] - p[2]) * axes.Normal[2];
  for (int i = 0; i < 3; ++i) ras[i] = world[i] - d * axes.Normal[i];
  return true;
}

void View::RASToDisplay(const double ras[3], double display[2]) const {
  vtkRenderer* renderer = this->Renderer;
  renderer->SetWorldPoint(ras[0], ras[1], ras[2], 1.0);
  renderer->WorldToDisplay();
  double out[3];
  renderer->GetDisplayPoint(out);
  display[0] = out[0];
  display[1] = out[1];
}

void View::Zoom(double factor) {
  if (factor <= 0) return;
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  if (this->IsSlice()) {
    camera->SetParallelScale(camera->GetParallelScale() / factor);
  } else {
    camera->Dolly(factor);
    this->Renderer->ResetCameraClippingRange();
  }
  this->RequestRender();
}

void View::Pan(const double deltaRAS[3]) {
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  double focal[3], position[3];
  camera->GetFocalPoint(focal);
  camera->GetPosition(position);
  for (int i = 0; i < 3; ++i) {
    focal[i] += deltaRAS[i];
    position[i] += deltaRAS[i];
  }
  camera->SetFocalPoint(focal);
  camera->SetPosition(position);
  this->RequestRender();
}

}  // namespace rp
