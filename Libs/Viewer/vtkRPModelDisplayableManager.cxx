#include "vtkRPModelDisplayableManager.h"

#include <vtkActor.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>

#include "rpView.h"
#include "vtkRPModelNode.h"

vtkStandardNewMacro(vtkRPModelDisplayableManager);

vtkRPModelDisplayableManager::~vtkRPModelDisplayableManager() { this->Finalize(); }

bool vtkRPModelDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPModelNode::SafeDownCast(node) != nullptr;
}

vtkActor* vtkRPModelDisplayableManager::GetActor(vtkRPNode* node) const {
  auto it = this->Actors.find(node);
  return it == this->Actors.end() ? nullptr : it->second.GetPointer();
}

void vtkRPModelDisplayableManager::AddDisplay(vtkRPNode* node) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkNew<vtkMatrix4x4> matrix;
  actor->SetUserMatrix(matrix);
  actor->GetProperty()->SetSpecular(0.2);
  actor->GetProperty()->SetSpecularPower(20);
  this->Actors[node] = actor;
  this->GetView()->GetRenderer()->AddActor(actor);
}

void vtkRPModelDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Actors.find(node);
  if (it == this->Actors.end()) return;
  if (this->GetView()) this->GetView()->GetRenderer()->RemoveActor(it->second);
  this->Actors.erase(it);
}

void vtkRPModelDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  vtkActor* actor = this->GetActor(node);
  if (!model || !actor) return;
  auto* mapper = vtkPolyDataMapper::SafeDownCast(actor->GetMapper());
  if (mapper->GetInput() != model->GetPolyData()) mapper->SetInputData(model->GetPolyData());
  actor->GetProperty()->SetColor(model->GetColor());
  actor->GetProperty()->SetOpacity(model->GetOpacity());
  actor->SetVisibility(model->GetVisibility() && model->GetPolyData() && model->GetPolyData()->GetNumberOfPoints() > 0);
  model->GetMatrixTransformToWorld(actor->GetUserMatrix());
  actor->GetUserMatrix()->Modified();
  actor->Modified();
}
