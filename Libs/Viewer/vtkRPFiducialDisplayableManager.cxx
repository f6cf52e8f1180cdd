#include "vtkRPFiducialDisplayableManager.h"

#include <cmath>
#include <string>
#include <vector>

#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCellArray.h>
#include <vtkGlyph3DMapper.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>

#include "rpView.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPFiducialDisplayableManager);

struct vtkRPFiducialDisplayableManager::Display {
  vtkNew<vtkPolyData> Points;
  vtkNew<vtkSphereSource> Sphere;
  vtkNew<vtkGlyph3DMapper> Mapper;
  vtkNew<vtkActor> Actor;
  std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> Labels;  // one per drawn point
  int Drawn = 0;
  Display() {
    this->Sphere->SetThetaResolution(16);
    this->Sphere->SetPhiResolution(12);
    this->Mapper->SetInputData(this->Points);
    this->Mapper->SetSourceConnection(this->Sphere->GetOutputPort());
    this->Mapper->ScalingOff();
    this->Mapper->ScalarVisibilityOff();
    this->Actor->SetMapper(this->Mapper);
    this->Actor->PickableOff();
  }
};

vtkRPFiducialDisplayableManager::~vtkRPFiducialDisplayableManager() { this->Finalize(); }

bool vtkRPFiducialDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPFiducialListNode::SafeDownCast(node) != nullptr;
}

int vtkRPFiducialDisplayableManager::GetNumberOfDrawnPoints(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() ? 0 : it->second->Drawn;
}

void vtkRPFiducialDisplayableManager::SetGlyphRadius(double radius) {
  this->GlyphRadius = radius;
  for (auto& entry : this->Displays) this->UpdateDisplay(entry.first);
}

void vtkRPFiducialDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto display = std::make_unique<Display>();
  vtkRenderer* renderer = this->GetView()->GetOverlayRenderer();
  renderer->AddActor(display->Actor);
  this->Displays[node] = std::move(display);
}

void vtkRPFiducialDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Displays.find(node);
  if (it == this->Displays.end()) return;
  if (this->GetView()) {
    vtkRenderer* renderer = this->GetView()->GetOverlayRenderer();
    renderer->RemoveActor(it->second->Actor);
    for (auto& label : it->second->Labels) renderer->RemoveActor(label);
  }
  this->Displays.erase(it);
}

void vtkRPFiducialDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* list = vtkRPFiducialListNode::SafeDownCast(node);
  auto it = this->Displays.find(node);
  if (!list || it == this->Displays.end()) return;
  Display& display = *it->second;
  rp::View* view = this->GetView();

  // In a slice view: only points on this slice (within half a scroll step).
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  const bool slice = sliceNode != nullptr;
  double normal[3] = {0, 0, 1};
  if (slice) sliceNode->GetNormal(normal);
  const double offset = slice ? sliceNode->GetSliceOffset() : 0.0;
  const double tolerance = 0.5 * view->GetSliceStep() + 1e-6;

  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> vertices;
  std::vector<std::string> labels;
  for (int i = 0; i < list->GetNumberOfControlPoints(); ++i) {
    if (!list->GetNthControlPoint(i).Visible) continue;
    double world[3];
    list->GetNthControlPointPositionWorld(i, world);
    if (slice) {
      const double distance = vtkMath::Dot(normal, world) - offset;
      if (std::fabs(distance) > tolerance) continue;
    }
    const vtkIdType id = points->InsertNextPoint(world);
    vertices->InsertNextCell(1, &id);
    labels.push_back(list->GetNthControlPoint(i).Label);
  }
  display.Points->SetPoints(points);
  display.Points->SetVerts(vertices);
  display.Points->Modified();
  display.Drawn = static_cast<int>(points->GetNumberOfPoints());
  display.Sphere->SetRadius(this->GlyphRadius);
  display.Actor->GetProperty()->SetColor(list->GetColor());
  display.Actor->SetVisibility(display.Drawn > 0);
  // Labels beside the points (billboards: always face the camera).
  vtkRenderer* renderer = view->GetOverlayRenderer();
  while (display.Labels.size() > labels.size()) {
    renderer->RemoveActor(display.Labels.back());
    display.Labels.pop_back();
  }
  while (display.Labels.size() < labels.size()) {
    auto label = vtkSmartPointer<vtkBillboardTextActor3D>::New();
    label->GetTextProperty()->SetFontSize(13);
    label->GetTextProperty()->ShadowOn();
    label->SetDisplayOffset(8, 8);
    label->PickableOff();
    renderer->AddActor(label);
    display.Labels.push_back(label);
  }
  for (size_t i = 0; i < labels.size(); ++i) {
    display.Labels[i]->SetInput(labels[i].c_str());
    display.Labels[i]->SetPosition(points->GetPoint(static_cast<vtkIdType>(i)));
    display.Labels[i]->GetTextProperty()->SetColor(list->GetColor());
  }
}

void vtkRPFiducialDisplayableManager::OnViewStateModified() {
  if (!this->GetView() || !this->GetView()->IsSlice()) return;
  for (auto& entry : this->Displays) this->UpdateDisplay(entry.first);
  this->RequestRender();
}
