#include "vtkRPModelSliceDisplayableManager.h"

#include <algorithm>

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>

#include "rpPlaneCutter.h"
#include "rpView.h"
#include "vtkRPModelNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPModelSliceDisplayableManager);

struct vtkRPModelSliceDisplayableManager::Outline {
  rp::PlaneCutter Cutter;
  vtkNew<vtkPolyData> Lines;  // in the model's coordinates
  vtkNew<vtkMatrix4x4> ModelToWorld;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  double CutNormal[3] = {0, 0, 0};  // the plane last cut with, in the model's coordinates
  double CutOffset = 0;
  vtkMTimeType CutMeshTime = 0;
  bool Dirty = true;
  Outline() {
    this->Mapper->SetInputData(this->Lines);
    this->Mapper->ScalarVisibilityOff();
    vtkRPDisplayableManager::SkipVertexShift(this->Mapper);  // re-cut whenever the slice moves
    this->Actor->SetMapper(this->Mapper);
    this->Actor->GetProperty()->SetLineWidth(2.0);
    this->Actor->GetProperty()->LightingOff();
    this->Actor->PickableOff();
    this->Actor->SetUserMatrix(this->ModelToWorld);
  }
};

vtkRPModelSliceDisplayableManager::vtkRPModelSliceDisplayableManager() {
  this->RenderCallback->SetClientData(this);
  this->RenderCallback->SetCallback([](vtkObject*, unsigned long, void* clientData, void*) {
    static_cast<vtkRPModelSliceDisplayableManager*>(clientData)->CutDirtyOutlines();
  });
}

// Cuts when the view renders, so many plane moves between two frames cost one cut.
void vtkRPModelSliceDisplayableManager::OnInitialize() {
  this->RenderTarget = this->GetView()->GetOverlayRenderer();
  this->RenderTag = this->RenderTarget->AddObserver(vtkCommand::StartEvent, this->RenderCallback);
}

void vtkRPModelSliceDisplayableManager::OnFinalize() {
  if (this->RenderTarget) this->RenderTarget->RemoveObserver(this->RenderTag);
  this->RenderTarget = nullptr;
}

void vtkRPModelSliceDisplayableManager::CutDirtyOutlines() {
  for (auto& entry : this->Outlines) {
    if (entry.second->Dirty) this->Cut(*entry.second);
  }
}

// The slice plane in the model's coordinates: with ModelToWorld = [A t], n·(A x + t) = n·o
// gives (Aᵀn)·x = n·(o − t).
void vtkRPModelSliceDisplayableManager::Cut(Outline& outline) {
  outline.Dirty = false;
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  vtkPolyData* mesh = outline.Cutter.GetInput();
  if (!sliceNode || !mesh || !outline.Actor->GetVisibility()) return;
  double origin[3], normal[3], t[3], local[3];
  sliceNode->GetOrigin(origin);
  sliceNode->GetNormal(normal);
  for (int r = 0; r < 3; ++r) {
    t[r] = outline.ModelToWorld->GetElement(r, 3);
    local[r] = 0;
    for (int c = 0; c < 3; ++c) local[r] += outline.ModelToWorld->GetElement(c, r) * normal[c];
  }
  const double d[3] = {origin[0] - t[0], origin[1] - t[1], origin[2] - t[2]};
  const double offset = vtkMath::Dot(normal, d);
  if (std::equal(local, local + 3, outline.CutNormal) && offset == outline.CutOffset && mesh->GetMTime() == outline.CutMeshTime) {
    return;  // the same plane through the same mesh
  }
  std::copy(local, local + 3, outline.CutNormal);
  outline.CutOffset = offset;
  outline.CutMeshTime = mesh->GetMTime();
  outline.Cutter.Cut(local, offset, outline.Lines);
}

vtkRPModelSliceDisplayableManager::~vtkRPModelSliceDisplayableManager() { this->Finalize(); }

bool vtkRPModelSliceDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPModelNode::SafeDownCast(node) != nullptr;
}

vtkPolyData* vtkRPModelSliceDisplayableManager::GetOutline(vtkRPNode* node) {
  auto it = this->Outlines.find(node);
  if (it == this->Outlines.end() || !it->second->Actor->GetVisibility()) return nullptr;
  if (it->second->Dirty) this->Cut(*it->second);
  return it->second->Lines;
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

void vtkRPModelSliceDisplayableManager::UpdatePlane(Outline& outline, vtkRPNode*) { outline.Dirty = true; }

void vtkRPModelSliceDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  auto it = this->Outlines.find(node);
  if (!model || it == this->Outlines.end()) return;
  Outline& outline = *it->second;
  vtkPolyData* polyData = model->GetPolyData();
  const bool visible = model->GetVisibility() && model->GetSliceIntersectionVisibility() && polyData &&
                       polyData->GetNumberOfPoints() > 0;
  outline.Actor->SetVisibility(visible);
  if (!visible) return;
  outline.Cutter.SetInput(polyData);
  model->GetMatrixTransformToWorld(outline.ModelToWorld);
  outline.ModelToWorld->Modified();
  outline.Actor->GetProperty()->SetColor(model->GetColor());
  // Opaque even for a see-through model: outlines are thin, and a translucent prop would cost
  // the view a full-screen transparency pass every frame.
  this->UpdatePlane(outline, node);
}

void vtkRPModelSliceDisplayableManager::OnViewStateModified() {
  for (auto& entry : this->Outlines) this->UpdatePlane(*entry.second, entry.first);
  this->RequestRender();
}
