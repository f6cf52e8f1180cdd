#include "vtkRPModelDisplayableManager.h"

#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkMassProperties.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkQuadricClustering.h>
#include <vtkRenderer.h>
#include <vtkTriangleFilter.h>

#include "rpView.h"
#include "vtkRPModelNode.h"

vtkStandardNewMacro(vtkRPModelDisplayableManager);

// Two mappers, so switching between full and light detail re-uploads nothing.
struct vtkRPModelDisplayableManager::Display {
  vtkNew<vtkActor> Actor;
  vtkNew<vtkPolyDataMapper> Full;
  vtkNew<vtkPolyDataMapper> Light;
  vtkSmartPointer<vtkPolyData> Decimated;
  vtkMTimeType DecimatedFrom = 0;  // the full mesh's time when Decimated was made
  double DecimatedBudget = 0;
  Display() {
    for (vtkPolyDataMapper* mapper : {this->Full.GetPointer(), this->Light.GetPointer()}) mapper->ScalarVisibilityOff();
    this->Actor->SetMapper(this->Full);
    vtkNew<vtkMatrix4x4> matrix;
    this->Actor->SetUserMatrix(matrix);
    this->Actor->GetProperty()->SetSpecular(0.2);
    this->Actor->GetProperty()->SetSpecularPower(20);
  }
};

namespace {

vtkIdType Triangles(vtkPolyData* mesh) { return mesh ? mesh->GetNumberOfPolys() + mesh->GetNumberOfStrips() : 0; }

vtkMTimeType MeshTime(vtkPolyData* mesh) {
  vtkMTimeType time = 0;
  if (mesh && mesh->GetPoints()) time = std::max(time, mesh->GetPoints()->GetMTime());
  if (mesh && mesh->GetPolys()) time = std::max(time, mesh->GetPolys()->GetMTime());
  return time;
}

// Quadric clustering to about `target` triangles: a surface of area A clustered into cubes of
// side h keeps roughly 2·A/h² triangles.
vtkSmartPointer<vtkPolyData> Decimate(vtkPolyData* mesh, double target) {
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(mesh);
  vtkNew<vtkMassProperties> area;
  area->SetInputConnection(triangles->GetOutputPort());
  area->Update();
  const double side = std::sqrt(2.0 * std::max(1e-9, area->GetSurfaceArea()) / std::max(100.0, target));
  vtkNew<vtkQuadricClustering> clustering;
  clustering->SetInputConnection(triangles->GetOutputPort());
  clustering->AutoAdjustNumberOfDivisionsOff();
  double bounds[6];
  mesh->GetBounds(bounds);
  int divisions[3];
  for (int i = 0; i < 3; ++i) divisions[i] = std::clamp(static_cast<int>(std::ceil((bounds[2 * i + 1] - bounds[2 * i]) / side)), 2, 1024);
  clustering->SetNumberOfDivisions(divisions);
  clustering->UseInputPointsOff();
  clustering->UseFeatureEdgesOff();
  clustering->Update();
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(clustering->GetOutput());
  return result;
}

}  // namespace

vtkRPModelDisplayableManager::~vtkRPModelDisplayableManager() { this->Finalize(); }

bool vtkRPModelDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPModelNode::SafeDownCast(node) != nullptr;
}

vtkActor* vtkRPModelDisplayableManager::GetActor(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() ? nullptr : it->second->Actor.GetPointer();
}

vtkPolyData* vtkRPModelDisplayableManager::GetDrawnPolyData(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() ? nullptr : vtkPolyData::SafeDownCast(it->second->Actor->GetMapper()->GetInput());
}

void vtkRPModelDisplayableManager::SetInteractiveTriangleBudget(double triangles) {
  this->InteractiveTriangleBudget = std::max(1000.0, triangles);
  for (auto& entry : this->Displays) this->ChooseDetail(entry.first, *entry.second);
}

void vtkRPModelDisplayableManager::SetInteractive(bool interactive) {
  if (interactive == this->Interactive) return;
  this->Interactive = interactive;
  for (auto& entry : this->Displays) this->ChooseDetail(entry.first, *entry.second);
}

void vtkRPModelDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto display = std::make_unique<Display>();
  this->GetView()->GetRenderer()->AddActor(display->Actor);
  this->Displays[node] = std::move(display);
}

void vtkRPModelDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Displays.find(node);
  if (it == this->Displays.end()) return;
  if (this->GetView()) this->GetView()->GetRenderer()->RemoveActor(it->second->Actor);
  this->Displays.erase(it);
}

// Each visible model gets its share of the budget (by its size among the visible models);
// meshes already under their share are drawn as they are.
vtkPolyData* vtkRPModelDisplayableManager::LightMesh(vtkRPNode* node, Display& display) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  vtkPolyData* mesh = model ? model->GetPolyData() : nullptr;
  if (!mesh || !model->GetVisibility()) return nullptr;
  double visible = 0;
  for (auto& entry : this->Displays) {
    auto* other = vtkRPModelNode::SafeDownCast(entry.first);
    if (other && other->GetVisibility()) visible += double(Triangles(other->GetPolyData()));
  }
  const double share = this->InteractiveTriangleBudget * double(Triangles(mesh)) / std::max(1.0, visible);
  if (double(Triangles(mesh)) <= 1.5 * share) {
    display.DecimatedFrom = MeshTime(mesh);  // drawn as it is: nothing to prepare
    return nullptr;
  }
  if (!display.Decimated || display.DecimatedFrom != MeshTime(mesh) || std::fabs(display.DecimatedBudget - share) > 0.25 * share) {
    display.Decimated = Decimate(mesh, share);
    display.DecimatedFrom = MeshTime(mesh);
    display.DecimatedBudget = share;
    display.Light->SetInputData(display.Decimated);
  }
  return display.Decimated;
}

void vtkRPModelDisplayableManager::ChooseDetail(vtkRPNode* node, Display& display) {
  vtkMapper* wanted = this->Interactive && this->LightMesh(node, display) ? display.Light.GetPointer() : display.Full.GetPointer();
  if (display.Actor->GetMapper() != wanted) display.Actor->SetMapper(wanted);
}

void vtkRPModelDisplayableManager::PrepareInteractiveDetail() {
  this->PreparePending = false;
  for (auto& entry : this->Displays) this->LightMesh(entry.first, *entry.second);
}

// Before a render that follows new or changed models: their light copies are made now, with
// every model of the scene known (so each is decimated once, to its final share).
void vtkRPModelDisplayableManager::OnRenderStart(vtkObject*, unsigned long, void* clientData, void*) {
  auto* self = static_cast<vtkRPModelDisplayableManager*>(clientData);
  if (self->PreparePending) self->PrepareInteractiveDetail();
}

void vtkRPModelDisplayableManager::OnInitialize() {
  this->RenderCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->RenderCallback->SetClientData(this);
  this->RenderCallback->SetCallback(&vtkRPModelDisplayableManager::OnRenderStart);
  this->RenderTag = this->GetView()->GetRenderer()->AddObserver(vtkCommand::StartEvent, this->RenderCallback);
}

void vtkRPModelDisplayableManager::OnFinalize() {
  if (this->GetView() && this->RenderTag) this->GetView()->GetRenderer()->RemoveObserver(this->RenderTag);
  this->RenderTag = 0;
}

void vtkRPModelDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  auto it = this->Displays.find(node);
  if (!model || it == this->Displays.end()) return;
  Display& display = *it->second;
  vtkActor* actor = display.Actor;
  if (display.Full->GetInput() != model->GetPolyData()) display.Full->SetInputData(model->GetPolyData());
  actor->GetProperty()->SetColor(model->GetColor());
  actor->GetProperty()->SetOpacity(model->GetOpacity());
  actor->GetProperty()->SetBackfaceCulling(model->GetOpacity() < 1.0);  // one blended layer
  actor->SetVisibility(model->GetVisibility() && model->GetPolyData() && model->GetPolyData()->GetNumberOfPoints() > 0);
  model->GetMatrixTransformToWorld(actor->GetUserMatrix());
  actor->GetUserMatrix()->Modified();
  actor->Modified();
  // A model not yet given its light copy (new, or a new mesh while still): before the next render.
  if (!this->Interactive && display.DecimatedFrom != MeshTime(model->GetPolyData())) this->PreparePending = true;
  this->ChooseDetail(node, display);
}
