#include "vtkRPPlanDisplayableManager.h"

#include <cmath>

#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkLineSource.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPlaneSource.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTriangleFilter.h>
#include <vtkTubeFilter.h>

#include "rpPlaneCutter.h"
#include "rpView.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrajectoryNode.h"

vtkStandardNewMacro(vtkRPPlanDisplayableManager);

struct vtkRPPlanDisplayableManager::Display {
  vtkNew<vtkPolyData> Surface;  // world RAS: the tool's cylinder or the plane's rectangle
  vtkNew<vtkPolyData> Drawn;    // what the actor shows (the surface in 3D, outline + axis on a slice)
  double Axis[2][3] = {{0, 0, 0}, {0, 0, 0}};  // a trajectory's entry and target (world)
  bool IsTrajectory = false;
  rp::PlaneCutter Cutter;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  Display() {
    this->Mapper->SetInputData(this->Drawn);
    this->Mapper->ScalarVisibilityOff();
    this->Actor->SetMapper(this->Mapper);
    this->Actor->PickableOff();
  }
};

vtkRPPlanDisplayableManager::~vtkRPPlanDisplayableManager() { this->Finalize(); }

bool vtkRPPlanDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPTrajectoryNode::SafeDownCast(node) || vtkRPCutPlaneNode::SafeDownCast(node);
}

vtkPolyData* vtkRPPlanDisplayableManager::GetDrawnGeometry(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() || !it->second->Actor->GetVisibility() ? nullptr : it->second->Drawn.GetPointer();
}

void vtkRPPlanDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto display = std::make_unique<Display>();
  // Plans move while they are dragged: the layer drawn every frame (with tools and fiducials).
  this->GetView()->GetOverlayRenderer()->AddActor(display->Actor);
  this->Displays[node] = std::move(display);
}

void vtkRPPlanDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Displays.find(node);
  if (it == this->Displays.end()) return;
  if (this->GetView()) this->GetView()->GetOverlayRenderer()->RemoveActor(it->second->Actor);
  this->Displays.erase(it);
}

// The plan's surface in world RAS.
void vtkRPPlanDisplayableManager::Rebuild(vtkRPNode* node, Display& display) {
  display.Surface->Initialize();
  if (auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(node)) {
    display.IsTrajectory = true;
    if (!trajectory->GetEntryWorld(display.Axis[0]) || !trajectory->GetTargetWorld(display.Axis[1]) ||
        vtkMath::Distance2BetweenPoints(display.Axis[0], display.Axis[1]) == 0)
      return;
    vtkNew<vtkLineSource> line;
    line->SetPoint1(display.Axis[0]);
    line->SetPoint2(display.Axis[1]);
    vtkNew<vtkTubeFilter> tube;
    tube->SetInputConnection(line->GetOutputPort());
    tube->SetRadius(0.5 * trajectory->GetToolDiameterMm());
    tube->SetNumberOfSides(24);
    tube->CappingOn();
    vtkNew<vtkTriangleFilter> triangles;
    triangles->SetInputConnection(tube->GetOutputPort());
    triangles->Update();
    display.Surface->DeepCopy(triangles->GetOutput());
    return;
  }
  auto* plane = vtkRPCutPlaneNode::SafeDownCast(node);
  double origin[3], normal[3], x[3], y[3];
  if (!plane || !plane->GetOriginWorld(origin)) return;
  plane->GetNormalWorld(normal);
  plane->GetXAxisWorld(x);
  vtkMath::Cross(normal, x, y);
  const double* size = plane->GetSize();
  vtkNew<vtkPlaneSource> source;
  double o[3], p1[3], p2[3];
  for (int i = 0; i < 3; ++i) {
    o[i] = origin[i] - 0.5 * size[0] * x[i] - 0.5 * size[1] * y[i];
    p1[i] = o[i] + size[0] * x[i];
    p2[i] = o[i] + size[1] * y[i];
  }
  source->SetOrigin(o);
  source->SetPoint1(p1);
  source->SetPoint2(p2);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(source->GetOutputPort());
  triangles->Update();
  display.Surface->DeepCopy(triangles->GetOutput());
}

// A slice view: where the slice cuts the surface, and a trajectory's axis projected onto it.
void vtkRPPlanDisplayableManager::CutWithSlice(Display& display) {
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  display.Drawn->Initialize();
  if (!sliceNode || display.Surface->GetNumberOfPoints() == 0) return;
  double origin[3], normal[3];
  sliceNode->GetOrigin(origin);
  sliceNode->GetNormal(normal);
  display.Cutter.SetInput(display.Surface);
  display.Cutter.Cut(normal, vtkMath::Dot(normal, origin), display.Drawn);
  if (!display.IsTrajectory) return;
  vtkPoints* points = display.Drawn->GetPoints();
  vtkCellArray* lines = display.Drawn->GetLines();
  if (!points || !lines) return;
  vtkIdType ids[2];
  for (int e = 0; e < 2; ++e) {
    const double d = vtkMath::Dot(normal, display.Axis[e]) - vtkMath::Dot(normal, origin);
    const double projected[3] = {display.Axis[e][0] - d * normal[0], display.Axis[e][1] - d * normal[1],
                                 display.Axis[e][2] - d * normal[2]};
    ids[e] = points->InsertNextPoint(projected);
  }
  lines->InsertNextCell(2, ids);
  display.Drawn->Modified();
}

void vtkRPPlanDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto it = this->Displays.find(node);
  if (it == this->Displays.end()) return;
  Display& display = *it->second;
  this->Rebuild(node, display);
  auto* markups = vtkRPMarkupsNode::SafeDownCast(node);
  display.Actor->GetProperty()->SetColor(markups->GetColor());
  display.Actor->GetProperty()->LightingOff();
  if (this->GetSliceNode()) {
    this->CutWithSlice(display);
    display.Actor->GetProperty()->SetLineWidth(2.0);
    display.Actor->GetProperty()->SetOpacity(1.0);
  } else {
    display.Drawn->DeepCopy(display.Surface);
    display.Actor->GetProperty()->LightingOn();
    display.Actor->GetProperty()->SetOpacity(display.IsTrajectory ? 0.7 : 0.35);
    display.Actor->GetProperty()->BackfaceCullingOn();
  }
  display.Actor->SetVisibility(display.Drawn->GetNumberOfPoints() > 0);
  this->RequestRender();
}

void vtkRPPlanDisplayableManager::OnViewStateModified() {
  if (!this->GetSliceNode()) return;
  for (auto& entry : this->Displays) {
    this->CutWithSlice(*entry.second);
    entry.second->Actor->SetVisibility(entry.second->Drawn->GetNumberOfPoints() > 0);
  }
  this->RequestRender();
}
