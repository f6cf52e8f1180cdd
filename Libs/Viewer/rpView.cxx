#include "rpView.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCoordinate.h>
#include <vtkCullerCollection.h>
#include <vtkLineSource.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "rpOrientationMarker.h"
#include "vtkRPCachedRenderPass.h"
#include "vtkRPFiducialDisplayableManager.h"
#include "vtkRPModelDisplayableManager.h"
#include "vtkRPModelNode.h"
#include "vtkRPModelSliceDisplayableManager.h"
#include "vtkRPImageNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"
#include "vtkRPToolDisplayableManager.h"
#include "vtkRPViewState.h"
#include "vtkRPViewportImageActor.h"
#include "vtkRPVolumeSliceDisplayableManager.h"

namespace rp {

namespace {
// Slice cameras sit this far from the plane; overlays up to this far on either side are drawn.
constexpr double SliceCameraDistance = 2000.0;
constexpr double DefaultFieldOfView = 250.0;  // mm, when there is nothing to fit (Slicer's)
constexpr double FitMargin = 1.05;

void Column(const vtkMatrix4x4* m, int c, double v[3]) {
  for (int r = 0; r < 3; ++r) v[r] = m->GetElement(r, c);
}

// The view colour of a slice node: Slicer's by layout name (the node may show any orientation).
void NodeColor(vtkRPSliceNode* node, double rgb[3]) {
  const std::string name = node ? node->GetLayoutName() : "";
  const ViewKind kind = name == "Yellow" ? ViewKind::Sagittal : name == "Green" ? ViewKind::Coronal : ViewKind::Axial;
  GetViewColor(kind, rgb);
}

// The image a slice view is fitted to and steps through: its background volume, else its
// segmentation (shown alone, as Slicer shows a segmentation without a volume).
vtkRPImageNode* ShownImageOf(vtkRPScene* scene, vtkRPSliceNode* node) {
  if (!scene || !node) return nullptr;
  for (const std::string& id : {node->GetBackgroundVolumeID(), node->GetLabelNodeID()}) {
    auto* image = vtkRPImageNode::SafeDownCast(scene->GetNodeByID(id));
    if (image && image->GetImageData() && image->GetImageData()->GetNumberOfPoints() > 0) return image;
  }
  return nullptr;
}
}  // namespace

View::View(ViewKind kind, vtkRPScene* scene, vtkRPViewState* state, const SliceViewNodes& slices)
    : Kind(kind), Scene(scene), State(state), Slices(slices) {
  this->Renderer->SetLayer(0);
  this->Overlay->SetLayer(1);
  // What moves is a few props, all in view: the frustum culler asked every one for its bounds
  // each frame (a pipeline update each), about a millisecond of a slice view's frame.
  this->Overlay->GetCullers()->RemoveAllItems();
  this->Overlay->InteractiveOff();
  this->Overlay->SetActiveCamera(this->Renderer->GetActiveCamera());
  if (this->IsSlice()) {
    this->Renderer->GetCullers()->RemoveAllItems();  // the picture alone
    this->Renderer->SetBackground(0, 0, 0);
    this->Renderer->GetActiveCamera()->ParallelProjectionOn();
    this->Managers.push_back(vtkSmartPointer<vtkRPVolumeSliceDisplayableManager>::New());
    this->Managers.push_back(vtkSmartPointer<vtkRPModelSliceDisplayableManager>::New());
  } else {
    this->Renderer->SetBackground(0.76, 0.76, 0.90);
    this->Renderer->SetBackground2(0.45, 0.45, 0.62);
    this->Renderer->GradientBackgroundOn();
    // Layer 0 holds what stands still while a tool moves (models, labels of the view): its
    // picture and depth are kept between frames (vtkRPCachedRenderPass). Layer 1 holds what
    // moves (tools, the slices in 3D, fiducials): drawn every frame over the kept picture,
    // depth-tested against the models, so opaque models hide them and see-through tissue does
    // not dim them. Both blend see-through surfaces in drawing order rather than with VTK's
    // default order-independent transparency, whose full-screen float passes cost a software
    // renderer more than the rest of the frame; their back faces are culled (a closed shell seen
    // from outside needs only its front), so the blend has one layer and order does not matter.
    this->Renderer->SetPass(this->ModelLayer);
    this->Overlay->PreserveDepthBufferOn();
    vtkNew<vtkRenderStepsPass> steps;
    this->Overlay->SetPass(steps);
    this->Managers.push_back(vtkSmartPointer<vtkRPVolumeSliceDisplayableManager>::New());
    this->Managers.push_back(vtkSmartPointer<vtkRPModelDisplayableManager>::New());
    this->Marker = std::make_unique<OrientationMarker>(this->Renderer);
  }
  this->Managers.push_back(vtkSmartPointer<vtkRPFiducialDisplayableManager>::New());
  this->Managers.push_back(vtkSmartPointer<vtkRPToolDisplayableManager>::New());

  // Crosshair: where the two other slice planes cut this one, in their views' colours.
  if (this->IsSlice()) {
    for (int i = 0; i < 2; ++i) {
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(this->CrossLines[i]->GetOutputPort());
      vtkRPDisplayableManager::SkipVertexShift(mapper);  // moves with the slice point
      this->CrossActors[i]->SetMapper(mapper);
      this->CrossActors[i]->PickableOff();
      this->CrossActors[i]->GetProperty()->SetLineWidth(1.0);  // opaque: no translucent pass per frame
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
  // While a tool moves the slice the offset changes every frame: drawn from cached glyphs into
  // the slice picture, it costs no FreeType rendering and no texture upload per frame.
  if (this->IsSlice()) this->CornerGlyphs.SetStyle(this->CornerText->GetTextProperty());

  for (auto& manager : this->Managers) manager->Initialize(this);

  // A slice view follows its node (camera, text) and the other nodes (crosshair).
  this->SliceCallback->SetClientData(this);
  this->SliceCallback->SetCallback(&View::OnSliceNodeModified);
  if (this->IsSlice()) {
    for (vtkRPSliceNode* node : this->Slices.Nodes) {
      if (node) this->SliceTags.emplace_back(node, node->AddObserver(vtkCommand::ModifiedEvent, this->SliceCallback));
    }
  }
  // The aspect ratio is known only when the view renders (the host may resize it).
  this->RenderCallback->SetClientData(this);
  this->RenderCallback->SetCallback(&View::OnRenderStart);
  this->RenderTag = this->Renderer->AddObserver(vtkCommand::StartEvent, this->RenderCallback);
  this->UpdateSliceCamera();
  this->UpdateCrosshair();
  this->UpdateCornerText();
}

View::~View() {
  for (auto& [node, tag] : this->SliceTags) {
    if (node) node->RemoveObserver(tag);
  }
  this->Renderer->RemoveObserver(this->RenderTag);
  for (auto& manager : this->Managers) manager->Finalize();
  this->DetachFromRenderWindow();
}

vtkRPSliceNode* View::GetSliceNode() const {
  return this->IsSlice() ? this->Slices.Nodes[static_cast<size_t>(this->Kind)] : nullptr;
}

vtkRPSliceLogic* View::GetSliceLogic() const {
  return this->IsSlice() ? this->Slices.Logics[static_cast<size_t>(this->Kind)] : nullptr;
}

void View::StartPicture() {
  if (vtkRPSliceLogic* logic = this->GetSliceLogic()) logic->StartPicture();
}

void View::WaitForPicture() {
  if (vtkRPSliceLogic* logic = this->GetSliceLogic()) logic->WaitForPicture();
}

vtkRenderer* View::GetOverlayRenderer() const { return this->Overlay; }

void View::AttachToRenderWindow(vtkRenderWindow* window, const double viewport[4]) {
  this->DetachFromRenderWindow();
  this->Window = window;
  window->SetNumberOfLayers(std::max(2, window->GetNumberOfLayers()));
  this->Renderer->SetViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  this->Overlay->SetViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  window->AddRenderer(this->Renderer);
  window->AddRenderer(this->Overlay);
  if (this->Marker) this->Marker->Attach(window, viewport);
  this->UpdateSliceCamera();
  this->RequestRender();
}

void View::DetachFromRenderWindow() {
  if (!this->Window) return;
  this->Window->RemoveRenderer(this->Renderer);
  this->Window->RemoveRenderer(this->Overlay);
  if (this->Marker) this->Marker->Detach();
  this->Window = nullptr;
}

void View::RequestRender() {
  this->RenderRequested = true;
  if (this->OnRenderRequest) this->OnRenderRequest();
}

void View::SetInteractive(bool interactive) {
  // While only layer 1 moves (a tool, the slices following it) the kept picture of the models is
  // copied and they stay at full detail; they are drawn light only while the camera moves (the
  // cause, not "the models were drawn last frame", which the switch to light meshes itself causes).
  if (!this->IsSlice() && this->ModelLayer->GetCaching()) {
    const vtkMTimeType cameraTime = this->Renderer->GetActiveCamera()->GetMTime();
    interactive = interactive && cameraTime != this->CameraTimeAtLastFrame;
    this->CameraTimeAtLastFrame = cameraTime;
  }
  if (interactive == this->Interactive) return;
  this->Interactive = interactive;
  for (auto& manager : this->Managers) manager->SetInteractive(interactive);
}

void View::SetModelLayerCaching(bool caching) {
  this->ModelLayer->SetCaching(caching);
  this->RequestRender();
}

bool View::GetModelLayerCaching() const { return this->ModelLayer->GetCaching(); }

void View::OnSliceNodeModified(vtkObject* caller, unsigned long, void* clientData, void*) {
  auto* self = static_cast<View*>(clientData);
  if (caller == self->GetSliceNode()) {
    self->UpdateSliceCamera();
    self->UpdateCornerText();
  }
  self->UpdateCrosshair();
  self->RequestRender();
}

void View::OnRenderStart(vtkObject*, unsigned long, void* clientData, void*) {
  auto* self = static_cast<View*>(clientData);
  if (!self->IsSlice()) return;
  if (self->GetViewportAspect() != self->LastAspect) self->UpdateSliceCamera();
  // The text actor only where no slice picture carries the text.
  bool drawnInPicture = false;
  for (auto& manager : self->Managers) {
    if (auto* slices = vtkRPVolumeSliceDisplayableManager::SafeDownCast(manager)) {
      vtkProp* picture = slices->GetScreenPictureActor();
      drawnInPicture = drawnInPicture || (picture && picture->GetVisibility());
    }
  }
  self->CornerText->SetVisibility(!drawnInPicture);
}

void View::DrawCornerText(unsigned char* picture, int width, int height) {
  // Where the text actor stands: 6 pixels in from the view's lower-left corner.
  this->CornerGlyphs.Draw(this->CornerString, 6, 6, picture, width, height);
}

double View::GetViewportAspect() const {
  if (!this->Window) return 1.0;
  const int* size = this->Window->GetSize();
  double vp[4];
  this->Renderer->GetViewport(vp);
  const double w = size[0] * (vp[2] - vp[0]), h = size[1] * (vp[3] - vp[1]);
  return w > 0 && h > 0 ? w / h : 1.0;
}

double View::GetSliceStep() const {
  vtkRPImageNode* volume = ShownImageOf(this->Scene, this->GetSliceNode());
  if (!volume) return 1.0;
  double spacing[3];
  volume->GetSpacing(spacing);
  return std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
}

double View::GetSliceOffset() const {
  vtkRPSliceNode* node = this->GetSliceNode();
  return node ? node->GetSliceOffset() : 0.0;
}

// The camera shows the node's plane: centred on its pan point, at least its field of view,
// looking along −(right × up) so the screen's right and up are the node's.
void View::UpdateSliceCamera() {
  vtkRPSliceNode* node = this->GetSliceNode();
  if (!node) return;
  const vtkMatrix4x4* sliceToRAS = node->GetSliceToRAS();
  double x[3], y[3], toCamera[3];
  Column(sliceToRAS, 0, x);
  Column(sliceToRAS, 1, y);
  vtkMath::Cross(x, y, toCamera);
  const double* pan = node->GetXYOrigin();
  const double* fov = node->GetFieldOfView();
  double focal[3];
  for (int r = 0; r < 3; ++r) focal[r] = sliceToRAS->GetElement(r, 3) + pan[0] * x[r] + pan[1] * y[r];
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  camera->SetFocalPoint(focal);
  camera->SetPosition(focal[0] + SliceCameraDistance * toCamera[0], focal[1] + SliceCameraDistance * toCamera[1],
                      focal[2] + SliceCameraDistance * toCamera[2]);
  camera->SetViewUp(y);
  camera->SetClippingRange(1.0, 2.0 * SliceCameraDistance);
  this->LastAspect = this->GetViewportAspect();
  camera->SetParallelScale(0.5 * std::max(fov[1], fov[0] / this->LastAspect));
}

// The lines where the other slice planes cut this one (none for a parallel plane).
void View::UpdateCrosshair() {
  vtkRPSliceNode* own = this->GetSliceNode();
  if (!own) return;
  double n[3], p[3];
  own->GetNormal(n);
  own->GetOrigin(p);
  int line = 0;
  for (vtkRPSliceNode* other : this->Slices.Nodes) {
    if (!other || other == own || line > 1) continue;
    double m[3], q[3], direction[3];
    other->GetNormal(m);
    other->GetOrigin(q);
    vtkMath::Cross(n, m, direction);
    const double length2 = vtkMath::Dot(direction, direction);
    if (length2 < 1e-12) continue;
    // A point on both planes: p0 = ((d1 m − d2 n) × ... ) — solved as the closest point to the
    // line's direction through the two plane equations n·x = n·p, m·x = m·q.
    const double d1 = vtkMath::Dot(n, p), d2 = vtkMath::Dot(m, q);
    double a[3], b[3], point[3];
    vtkMath::Cross(m, direction, a);  // (m × dir)
    vtkMath::Cross(direction, n, b);  // (dir × n)
    for (int i = 0; i < 3; ++i) point[i] = (d1 * a[i] + d2 * b[i]) / length2;
    vtkMath::Normalize(direction);
    const double halfLength = 5000.0;
    this->CrossLines[line]->SetPoint1(point[0] - halfLength * direction[0], point[1] - halfLength * direction[1],
                                      point[2] - halfLength * direction[2]);
    this->CrossLines[line]->SetPoint2(point[0] + halfLength * direction[0], point[1] + halfLength * direction[1],
                                      point[2] + halfLength * direction[2]);
    double color[3];
    NodeColor(other, color);
    this->CrossActors[line]->GetProperty()->SetColor(color);
    this->CrossActors[line]->SetVisibility(true);
    ++line;
  }
  for (; line < 2; ++line) this->CrossActors[line]->SetVisibility(false);
}

void View::UpdateCornerText() {
  char text[96];
  vtkRPSliceNode* node = this->GetSliceNode();
  if (node) {
    static const char* const positive[3] = {"R", "A", "S"};
    static const char* const negative[3] = {"L", "P", "I"};
    double normal[3];
    node->GetNormal(normal);
    const double offset = node->GetSliceOffset();
    int axis = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::fabs(normal[i]) > std::fabs(normal[axis])) axis = i;
    }
    // The anatomical side of the plane: the normal's dominant axis, signed.
    const double side = offset * (normal[axis] >= 0 ? 1 : -1);
    const bool standard = node->GetOrientation() != vtkRPSliceNode::ReformatOrientationName();
    std::snprintf(text, sizeof(text), "%s  %s%s %.1f mm", node->GetOrientation().c_str(), standard ? "" : "~",
                  side >= 0 ? positive[axis] : negative[axis], std::fabs(offset));
  } else {
    std::snprintf(text, sizeof(text), "3D");
  }
  this->CornerText->SetInput(text);
  this->CornerString = text;
}

bool View::ComputeFramingBounds(double bounds[6]) const {
  vtkMath::UninitializeBounds(bounds);
  bool found = false;
  auto add = [&](const double b[6]) {
    if (!found) {
      std::copy(b, b + 6, bounds);
      found = true;
      return;
    }
    for (int i = 0; i < 3; ++i) {
      bounds[2 * i] = std::min(bounds[2 * i], b[2 * i]);
      bounds[2 * i + 1] = std::max(bounds[2 * i + 1], b[2 * i + 1]);
    }
  };
  if (!this->Scene) return false;
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    vtkPolyData* polyData = model->GetPolyData();
    if (!model->GetVisibility() || model->GetOpacity() <= 0 || !polyData || polyData->GetNumberOfPoints() == 0) continue;
    double b[6];
    polyData->GetBounds(b);
    vtkNew<vtkMatrix4x4> toWorld;
    model->GetMatrixTransformToWorld(toWorld);
    double world[6];
    vtkMath::UninitializeBounds(world);
    for (int c = 0; c < 8; ++c) {
      const double corner[4] = {b[(c & 1) ? 1 : 0], b[(c & 2) ? 3 : 2], b[(c & 4) ? 5 : 4], 1};
      double out[4];
      toWorld->MultiplyPoint(corner, out);
      for (int i = 0; i < 3; ++i) {
        world[2 * i] = c == 0 ? out[i] : std::min(world[2 * i], out[i]);
        world[2 * i + 1] = c == 0 ? out[i] : std::max(world[2 * i + 1], out[i]);
      }
    }
    add(world);
  }
  if (found) return true;
  for (vtkRPSliceNode* node : this->Slices.Nodes) {
    if (vtkRPImageNode* volume = ShownImageOf(this->Scene, node)) {
      double b[6];
      vtkRPSliceLogic::ComputeShownRASBounds(volume, b);
      add(b);
    }
  }
  return found;
}

void View::ResetCamera() {
  if (this->IsSlice()) {
    vtkRPSliceNode* node = this->GetSliceNode();
    if (!node) return;
    vtkRPImageNode* volume = ShownImageOf(this->Scene, node);
    if (!volume) {
      node->SetFieldOfView(DefaultFieldOfView, DefaultFieldOfView);
      node->SetXYOrigin(0, 0);
      return;
    }
    // Fit the image's extent (a segmentation's labelled voxels) in the plane, centred on it.
    double b[4];
    int extent[6];
    vtkRPSliceLogic::ComputeShownExtent(volume, extent);
    vtkRPSliceLogic::ComputePlaneBounds(volume, node->GetSliceToRAS(), b, extent);
    const double xmin = b[0], xmax = b[1], ymin = b[2], ymax = b[3];
    const int previous = node->StartModify();
    node->SetFieldOfView(std::max(1.0, FitMargin * (xmax - xmin)), std::max(1.0, FitMargin * (ymax - ymin)));
    node->SetXYOrigin(0.5 * (xmin + xmax), 0.5 * (ymin + ymax));
    node->EndModify(previous);
    this->UpdateSliceCamera();
    this->RequestRender();
    return;
  }
  // 3D: seen from the front (the patient's anterior), head up; the distance makes the framed
  // box's projection fill the view with a small margin (not VTK's bounding sphere, which leaves
  // a knee a tenth of the view).
  double bounds[6];
  if (!this->ComputeFramingBounds(bounds)) {
    for (int i = 0; i < 3; ++i) {
      bounds[2 * i] = -0.5 * DefaultFieldOfView;
      bounds[2 * i + 1] = 0.5 * DefaultFieldOfView;
    }
  }
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  const double center[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
  const double width = std::max(1.0, bounds[1] - bounds[0]);   // R–L on screen
  const double height = std::max(1.0, bounds[5] - bounds[4]);  // S–I on screen
  const double depth = std::max(1.0, bounds[3] - bounds[2]);   // A–P towards the camera
  const double aspect = this->GetViewportAspect();
  const double tanHalf = std::tan(vtkMath::RadiansFromDegrees(camera->GetViewAngle()) * 0.5);
  const double margin = 1.1;
  // Distance from the box's front face so that its width and height fit.
  const double fit = margin * 0.5 * std::max(height, width / aspect) / tanHalf;
  const double distance = fit + 0.5 * depth;
  camera->SetFocalPoint(center);
  camera->SetPosition(center[0], center[1] + distance, center[2]);  // anterior
  camera->SetViewUp(0, 0, 1);
  camera->OrthogonalizeViewUp();
  this->Renderer->ResetCameraClippingRange();
  this->RequestRender();
}

bool View::DisplayToRAS(double x, double y, double ras[3]) const {
  vtkRPSliceNode* node = this->GetSliceNode();
  if (!node) return false;
  vtkRenderer* renderer = this->Renderer;
  renderer->SetDisplayPoint(x, y, 0.5);
  renderer->DisplayToWorld();
  double world[4];
  renderer->GetWorldPoint(world);
  if (world[3] == 0.0) return false;
  for (int i = 0; i < 3; ++i) world[i] /= world[3];
  // Project onto the slice plane along its normal (parallel projection: the view direction).
  double normal[3], origin[3];
  node->GetNormal(normal);
  node->GetOrigin(origin);
  const double d = (world[0] - origin[0]) * normal[0] + (world[1] - origin[1]) * normal[1] + (world[2] - origin[2]) * normal[2];
  for (int i = 0; i < 3; ++i) ras[i] = world[i] - d * normal[i];
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
  if (!(factor > 0) || !std::isfinite(factor)) return;
  if (vtkRPSliceNode* node = this->GetSliceNode()) {
    const double* fov = node->GetFieldOfView();
    node->SetFieldOfView(fov[0] / factor, fov[1] / factor);  // the view follows the node
    return;
  }
  this->Renderer->GetActiveCamera()->Dolly(factor);
  this->Renderer->ResetCameraClippingRange();
  this->RequestRender();
}

void View::Pan(const double deltaRAS[3]) {
  if (vtkRPSliceNode* node = this->GetSliceNode()) {
    double x[3], y[3];
    Column(node->GetSliceToRAS(), 0, x);
    Column(node->GetSliceToRAS(), 1, y);
    const double* pan = node->GetXYOrigin();
    node->SetXYOrigin(pan[0] + vtkMath::Dot(deltaRAS, x), pan[1] + vtkMath::Dot(deltaRAS, y));
    return;
  }
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
