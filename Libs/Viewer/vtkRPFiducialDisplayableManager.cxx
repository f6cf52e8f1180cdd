#include "vtkRPFiducialDisplayableManager.h"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCoordinate.h>
#include <vtkRenderWindow.h>
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
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "rpLabelLayout.h"
#include "rpView.h"
#include "vtkRPMarkupsNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPFiducialDisplayableManager);

struct vtkRPFiducialDisplayableManager::Display {
  vtkNew<vtkPolyData> Points;
  vtkNew<vtkSphereSource> Sphere;
  vtkNew<vtkGlyph3DMapper> Mapper;
  vtkNew<vtkActor> Actor;
  std::vector<vtkSmartPointer<vtkTextActor>> Labels;  // one per drawn point, placed at render time
  std::vector<std::pair<std::string, std::array<double, 2>>> LabelSizes;  // text measured, its size
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

vtkRPFiducialDisplayableManager::vtkRPFiducialDisplayableManager() {
  this->LayoutCallback->SetClientData(this);
  this->LayoutCallback->SetCallback([](vtkObject*, unsigned long, void* clientData, void*) {
    static_cast<vtkRPFiducialDisplayableManager*>(clientData)->LayOutLabels();
  });
}

vtkRPFiducialDisplayableManager::~vtkRPFiducialDisplayableManager() { this->Finalize(); }

// Labels are laid out where the view renders (the camera and window size are final then).
void vtkRPFiducialDisplayableManager::OnInitialize() {
  this->LayoutRenderer = this->GetView()->GetOverlayRenderer();
  this->LayoutTag = this->LayoutRenderer->AddObserver(vtkCommand::StartEvent, this->LayoutCallback);
}

void vtkRPFiducialDisplayableManager::OnFinalize() {
  if (this->LayoutRenderer) this->LayoutRenderer->RemoveObserver(this->LayoutTag);
  this->LayoutRenderer = nullptr;
}

// Every label of this view beside its point, none over another (all lists together).
void vtkRPFiducialDisplayableManager::LayOutLabels() {
  vtkRenderer* renderer = this->LayoutRenderer;
  vtkRenderWindow* window = renderer ? renderer->GetRenderWindow() : nullptr;
  if (!window) return;
  std::vector<vtkTextActor*> actors;
  std::vector<rp::LabelBox> boxes;
  for (auto& entry : this->Displays) {
    Display& display = *entry.second;
    for (size_t i = 0; i < display.Labels.size(); ++i) {
      vtkTextActor* label = display.Labels[i];
      const double* world = display.Points->GetPoint(static_cast<vtkIdType>(i));
      renderer->SetWorldPoint(world[0], world[1], world[2], 1.0);
      renderer->WorldToDisplay();
      double d[3];
      renderer->GetDisplayPoint(d);
      const bool inFront = d[2] >= 0.0 && d[2] <= 1.0;  // not behind the camera
      label->SetVisibility(inFront && label->GetInput() && *label->GetInput());
      if (!label->GetVisibility()) continue;
      // The text's size is measured (FreeType) only when the text changed.
      auto& size = display.LabelSizes[i];
      if (size.first != label->GetInput() || size.second[0] < 0) {
        double bbox[4];
        label->GetBoundingBox(renderer, bbox);
        size.first = label->GetInput();
        size.second = {bbox[1] - bbox[0], bbox[3] - bbox[2]};
      }
      rp::LabelBox box;
      box.Anchor[0] = d[0];
      box.Anchor[1] = d[1];
      box.Size[0] = size.second[0];
      box.Size[1] = size.second[1];
      boxes.push_back(box);
      actors.push_back(label);
    }
  }
  const int* size = window->GetSize();
  double vp[4];
  renderer->GetViewport(vp);
  const double viewport[4] = {vp[0] * size[0], vp[1] * size[1], vp[2] * size[0], vp[3] * size[1]};
  const std::vector<rp::LabelPlacement> placements = rp::PlaceLabels(boxes, viewport);
  for (size_t i = 0; i < actors.size(); ++i) {
    actors[i]->GetPositionCoordinate()->SetValue(placements[i].Position[0], placements[i].Position[1]);
  }
}

bool vtkRPFiducialDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPMarkupsNode::SafeDownCast(node) != nullptr;  // fiducials, trajectories' ends, planes' origins
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
    for (auto& label : it->second->Labels) renderer->RemoveActor2D(label);
  }
  this->Displays.erase(it);
}

void vtkRPFiducialDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* list = vtkRPMarkupsNode::SafeDownCast(node);
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
  // Labels beside the points, on top of everything (placed when the view renders).
  vtkRenderer* renderer = view->GetOverlayRenderer();
  while (display.Labels.size() > labels.size()) {
    renderer->RemoveActor2D(display.Labels.back());
    display.Labels.pop_back();
  }
  while (display.Labels.size() < labels.size()) {
    auto label = vtkSmartPointer<vtkTextActor>::New();
    label->GetTextProperty()->SetFontSize(13);
    label->GetTextProperty()->ShadowOn();
    label->GetTextProperty()->SetBackgroundColor(0.05, 0.05, 0.05);
    label->GetTextProperty()->SetBackgroundOpacity(0.45);  // readable over bone and air alike
    label->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    label->PickableOff();
    renderer->AddActor2D(label);
    display.Labels.push_back(label);
  }
  display.LabelSizes.resize(labels.size(), {std::string(), {-1.0, -1.0}});
  for (size_t i = 0; i < labels.size(); ++i) {
    display.Labels[i]->SetInput(labels[i].c_str());
    display.Labels[i]->GetTextProperty()->SetColor(list->GetColor());
  }
}

void vtkRPFiducialDisplayableManager::OnViewStateModified() {
  if (!this->GetView() || !this->GetView()->IsSlice()) return;
  for (auto& entry : this->Displays) this->UpdateDisplay(entry.first);
  this->RequestRender();
}
