#include "vtkRPModelSliceDisplayableManager.h"

#include <vtkActor.h>
#include <vtkCutter.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPlane.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTransform.h>

#include "rpView.h"
#include "vtkRPModelNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPModelSliceDisplayableManager);

struct vtkRPModelSliceDisplayableManager::Outline {
  vtkNew<vtkPlane> Plane;
  vtkNew<vtkTransform> ModelToWorld;
  vtkNew<vtkCutter> Cutter;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  Outline() {
    // The plane is given in RAS; the function's transform maps model points to RAS first.
    this->Plane->SetTransform(this->ModelToWorld);
    this->Cutter->SetCutFunction(this->Plane);
    this->Cutter->GenerateTrianglesOff();
    this->Mapper->SetInputConnection(this->Cutter->GetOutputPort());
    this->Mapper->ScalarVisibilityOff();
    this->Actor->SetMapper(this->Mapper);
    this->Actor->GetProperty()->SetLineWidth(2.0);
    this->Actor->GetProperty()->LightingOff();
    this->Actor->PickableOff();
    vtkNew<vtkMatrix4x4> identity;
    this->Actor->SetUserMatrix(identity);
  }
};

vtkRPModelSliceDisplayableManager::~vtkRPModelSliceDisplayableManager() { this->Finalize(); }

bool vtkRPModelSliceDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPModelNode::SafeDownCast(node) != nullptr;
}

vtkPolyData* vtkRPModelSliceDisplayableManager::GetOutline(vtkRPNode* node) {
  auto it = this->Outlines.find(node);
  if (it == this->Outlines.end() || !it->second->Actor->GetVisibility()) return nullptr;
  it->second->Cutter->Update();
  return it->second->Cutter->GetOutput();
}

void vtkRPModelSliceDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto outline = std::make_unique<Outline>();
  this->GetView()->GetOverlayRenderer()->AddActor(outline->Actor);
  this->Outlines[node] = std::move(outline);
}

void vtkRPModelSliceDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Outlines.find(node);
  if (it == this->Outlines.end()) return;
  if (this->GetView()) this->GetView()->GetOverlayRenderer()->RemoveActor(it->second->Actor);
  this->Outlines.erase(it);
}

void vtkRPModelSliceDisplayableManager::UpdatePlane(Outline& outline, vtkRPNode*) {
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  if (!sliceNode) return;
  double origin[3], normal[3];
  sliceNode->GetOrigin(origin);
  sliceNode->GetNormal(normal);
  outline.Plane->SetOrigin(origin);  // unchanged values do not re-cut (vtkPlane's setters compare)
  outline.Plane->SetNormal(normal);
}

void vtkRPModelSliceDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  auto it = this->Outlines.find(node);
  if (!model || it == this->Outlines.end()) return;
  Outline& outline = *it->second;
  vtkPolyData* polyData = model->GetPolyData();
  const bool visible = model->GetVisibility() && polyData && polyData->GetNumberOfPoints() > 0;
  outline.Actor->SetVisibility(visible);
  if (!visible) return;
  if (outline.Cutter->GetInput() != polyData) outline.Cutter->SetInputData(polyData);
  vtkNew<vtkMatrix4x4> toWorld;
  model->GetMatrixTransformToWorld(toWorld);
  outline.ModelToWorld->SetMatrix(toWorld);
  outline.Actor->GetUserMatrix()->DeepCopy(toWorld);
  outline.Actor->GetProperty()->SetColor(model->GetColor());
  outline.Actor->GetProperty()->SetOpacity(model->GetOpacity() < 0.3 ? 0.6 : 1.0);
  this->UpdatePlane(outline, node);
}

void vtkRPModelSliceDisplayableManager::OnViewStateModified() {
  for (auto& entry : this->Outlines) this->UpdatePlane(*entry.second, entry.first);
  this->RequestRender();
}
