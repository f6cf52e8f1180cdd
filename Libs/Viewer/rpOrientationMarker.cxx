#include "rpOrientationMarker.h"

#include <algorithm>

#include <vtkAnnotatedCubeActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCullerCollection.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

namespace rp {

OrientationMarker::OrientationMarker(vtkRenderer* viewRenderer, double size) : ViewRenderer(viewRenderer), Size(size) {
  // RAS: +X is the patient's right, +Y anterior, +Z superior.
  this->Cube->SetXPlusFaceText("R");
  this->Cube->SetXMinusFaceText("L");
  this->Cube->SetYPlusFaceText("A");
  this->Cube->SetYMinusFaceText("P");
  this->Cube->SetZPlusFaceText("S");
  this->Cube->SetZMinusFaceText("I");
  this->Cube->SetFaceTextScale(0.65);
  this->Cube->GetCubeProperty()->SetColor(0.85, 0.85, 0.85);
  // No outlines round the letters: VTK recomputes them (feature edges of the letters' polygons)
  // on every frame, a millisecond of a software renderer's frame for a detail of a 100-pixel cube.
  this->Cube->SetTextEdgesVisibility(0);
  // Slicer's axis colours on the labels: R red, A green, S blue.
  for (auto* property : {this->Cube->GetXPlusFaceProperty(), this->Cube->GetXMinusFaceProperty()}) property->SetColor(0.85, 0.2, 0.2);
  for (auto* property : {this->Cube->GetYPlusFaceProperty(), this->Cube->GetYMinusFaceProperty()}) property->SetColor(0.2, 0.65, 0.2);
  for (auto* property : {this->Cube->GetZPlusFaceProperty(), this->Cube->GetZMinusFaceProperty()}) property->SetColor(0.2, 0.35, 0.9);
  this->Cube->PickableOff();
  this->Renderer->AddViewProp(this->Cube);
  this->Renderer->InteractiveOff();
  this->Renderer->GetCullers()->RemoveAllItems();  // always in view: no bounds to compute per frame
  this->Renderer->SetLayer(2);  // over the view's two layers
  this->Callback->SetClientData(this);
  this->Callback->SetCallback(&OrientationMarker::OnViewRender);
  this->Tag = viewRenderer->AddObserver(vtkCommand::StartEvent, this->Callback);
}

OrientationMarker::~OrientationMarker() {
  this->Detach();
  this->ViewRenderer->RemoveObserver(this->Tag);
}

void OrientationMarker::Attach(vtkRenderWindow* window, const double viewViewport[4]) {
  this->Detach();
  this->Window = window;
  std::copy(viewViewport, viewViewport + 4, this->ViewViewport);
  window->SetNumberOfLayers(std::max(3, window->GetNumberOfLayers()));
  window->AddRenderer(this->Renderer);
  this->UpdateCamera();
}

void OrientationMarker::Detach() {
  if (this->Window) this->Window->RemoveRenderer(this->Renderer);
  this->Window = nullptr;
}

void OrientationMarker::OnViewRender(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<OrientationMarker*>(clientData)->UpdateCamera();
}

// Same direction and up as the view's camera, at a fixed distance; a square viewport in the
// view's bottom-right corner.
void OrientationMarker::UpdateCamera() {
  if (!this->Window) return;
  const int* size = this->Window->GetSize();
  const double* v = this->ViewViewport;
  const double width = (v[2] - v[0]) * size[0], height = (v[3] - v[1]) * size[1];
  const double side = this->Size * std::min(width, height);
  if (width <= 0 || height <= 0 || size[0] <= 0 || size[1] <= 0) return;
  this->Renderer->SetViewport(v[2] - side / size[0], v[1], v[2], v[1] + side / size[1]);

  vtkCamera* view = this->ViewRenderer->GetActiveCamera();
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  double direction[3];
  view->GetDirectionOfProjection(direction);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(-3.2 * direction[0], -3.2 * direction[1], -3.2 * direction[2]);
  camera->SetViewUp(view->GetViewUp());
  camera->SetViewAngle(30);
  camera->ParallelProjectionOff();
  camera->SetClippingRange(1.0, 6.0);  // the unit cube seen from 3.2 away, whichever way it turns
}

}  // namespace rp
