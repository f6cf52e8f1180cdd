#include "vtkRPNavigationLogic.h"

#include <cmath>
#include <sstream>

#include <vtkCallbackCommand.h>
#include <vtkGenericCell.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>
#include <vtkTriangle.h>

#include "rpGuidedDrill.h"
#include "rpIgtlOutbox.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpIgtlServer.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"
#include "vtkRPTransformableNode.h"

vtkStandardNewMacro(vtkRPNavigationLogic);

vtkRPNavigationLogic::vtkRPNavigationLogic()
    : Planning(vtkSmartPointer<vtkRPPlanningLogic>::New()), Outbox(std::make_unique<rp::IgtlOutbox>()) {
  this->ToolCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->ToolCallback->SetClientData(this);
  this->ToolCallback->SetCallback(&vtkRPNavigationLogic::OnToolMoved);
}

vtkRPNavigationLogic::~vtkRPNavigationLogic() {
  this->StopReadoutServer();
  if (this->ObservedTool) this->ObservedTool->RemoveObserver(this->ToolObserverTag);
}

void vtkRPNavigationLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ToolNodeID: " << this->ToolNodeID << "\n" << indent << "WarningDistance: " << this->WarningDistance << "\n";
}

void vtkRPNavigationLogic::SetScene(vtkRPScene* scene) {
  this->Scene = scene;
  this->Planning->SetScene(scene);
  this->ObserveTool();
}

void vtkRPNavigationLogic::SetToolNodeID(const std::string& id) {
  this->ToolNodeID = id;
  this->ObserveTool();
  this->Modified();
}

void vtkRPNavigationLogic::SetTargetModelNodeIDs(const std::vector<std::string>& ids) {
  this->TargetModelNodeIDs = ids;
  this->Modified();
}

void vtkRPNavigationLogic::SetTrajectoryNodeID(const std::string& id) {
  this->TrajectoryNodeID = id;
  this->Modified();
}

bool vtkRPNavigationLogic::PrepareScore(const rp::ScoreRequest& request, rp::ScoredExecution& job, std::string& error) {
  job.Request = request;
  if (!this->Scene) {
    error = "no scene";
    return false;
  }
  job.Plan = this->Planning->MakePlanSnapshot(error);
  if (!job.Plan) return false;
  if (job.Plan->Trajectories.empty()) {
    error = "the scene holds no complete trajectory (a Slicer markups line: entry and target)";
    return false;
  }
  const rp::TrajectorySnapshot* trajectory = rp::ChooseTrajectory(*job.Plan, request.Trajectory, error);
  if (!trajectory) return false;
  job.Trajectory = *trajectory;
  job.BoneName.clear();
  job.BoneSurface.reset();
  if (request.BoneModelNodeID.empty()) return true;
  auto* bone = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(request.BoneModelNodeID));
  if (!bone) {
    error = "the scene has no model '" + request.BoneModelNodeID + "' for the bone";
    return false;
  }
  vtkNew<vtkMatrix4x4> toWorld;
  bone->GetMatrixTransformToWorld(toWorld);
  auto surface = std::make_shared<rp::TriangleMesh>();
  if (!rp::PolyDataToTriangleMesh(bone->GetPolyData(), toWorld, *surface, error)) {
    error = "the bone '" + bone->GetName() + "' has no surface: " + error;
    return false;
  }
  job.BoneName = bone->GetName();
  job.BoneSurface = std::move(surface);
  return true;
}

bool vtkRPNavigationLogic::ScoreExecution(const rp::ScoreRequest& request, rp::ScoredExecution& result, std::string& error) {
  return this->PrepareScore(request, result, error) && rp::RunScore(result, error);
}

void vtkRPNavigationLogic::UpdateReadout(vtkRPTransformableNode* tool) {
  this->LastReadout = rp::GuidanceReadout{};
  auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(this->Scene->GetNodeByID(this->TrajectoryNodeID));
  double entry[3], target[3];
  rp::TrajectoryAxis plan;
  std::string error;
  if (!tool || !trajectory || !trajectory->GetEntryWorld(entry) || !trajectory->GetTargetWorld(target) ||
      !rp::TrajectoryAxis::Make({entry[0], entry[1], entry[2]}, {target[0], target[1], target[2]}, plan, error)) {
    if (tool) tool->RemoveAttribute("Navigation.Guidance");
    return;
  }
  vtkNew<vtkMatrix4x4> toWorld;
  tool->GetMatrixTransformToWorld(toWorld);
  double tipToRAS[16];
  vtkMatrix4x4::DeepCopy(tipToRAS, toWorld);  // row-major, as ComputeReadout takes it
  const double toolRadius = 0.5 * trajectory->GetToolDiameterMm();
  this->LastReadout = rp::ComputeReadout(plan, tipToRAS, this->CurrentStructures(), toolRadius);
  tool->SetAttribute("Navigation.Guidance", rp::ReadoutString(this->LastReadout));
  this->PublishReadout();
}

std::vector<rp::ReadoutStructure> vtkRPNavigationLogic::CurrentStructures() {
  // The Planning logic's snapshot is rebuilt only when a structure changed: a query per move.
  this->StructuresProblem.clear();
  if (!this->Planning->GetStructuresAtRiskSnapshot(this->Structures, this->StructuresProblem)) this->Structures.clear();
  std::vector<rp::ReadoutStructure> structures;
  for (const rp::StructureAtRiskSnapshot& s : this->Structures) {
    if (s.Signed) structures.push_back({s.Name, s.Signed.get(), s.SafetyMarginMm});
    else this->StructuresProblem = "structure at risk '" + s.Name + "' has an open surface: no inside, not measured";
  }
  return structures;
}

void vtkRPNavigationLogic::PublishReadout() {
  if (!this->LastReadout.Valid) return;
  this->Outbox->PublishTransform(rp::ReadoutTransformName, this->LastReadout.ToolTipToTrajectory);
  this->Outbox->PublishString(rp::ReadoutStringName, rp::ReadoutString(this->LastReadout));
}

bool vtkRPNavigationLogic::StartReadoutServer(int port, std::string& error, const std::string& bindAddress) {
  this->StopReadoutServer();
  if (!this->NoPoses) this->NoPoses = std::make_unique<rp::ToolPoseTable>();
  rp::IgtlServer::Options options;
  options.Port = port;
  options.BindAddress = bindAddress;
  options.Outbox = this->Outbox.get();
  options.CommandClients = rp::AddressAllowList{};  // it streams read-outs: no client records or sets transforms
  auto server = std::make_unique<rp::IgtlServer>(*this->NoPoses, options);
  if (!server->Start(error)) return false;
  this->Server = std::move(server);
  return true;
}

void vtkRPNavigationLogic::StopReadoutServer() { this->Server.reset(); }

int vtkRPNavigationLogic::GetReadoutServerPort() const { return this->Server ? this->Server->Port() : 0; }

int vtkRPNavigationLogic::GetReadoutClientCount() const { return this->Server ? this->Server->ClientCount() : 0; }

void vtkRPNavigationLogic::ObserveTool() {
  vtkObject* tool = this->Scene ? this->Scene->GetNodeByID(this->ToolNodeID) : nullptr;
  if (tool == this->ObservedTool) return;
  if (this->ObservedTool) this->ObservedTool->RemoveObserver(this->ToolObserverTag);
  this->ObservedTool = tool;
  if (tool) this->ToolObserverTag = tool->AddObserver(vtkRPNode::TransformModifiedEvent, this->ToolCallback);
}

void vtkRPNavigationLogic::OnToolMoved(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<vtkRPNavigationLogic*>(clientData)->Update();
}

void vtkRPNavigationLogic::GetTipRAS(vtkRPTransformableNode* tool, double tipRAS[3]) {
  vtkNew<vtkMatrix4x4> toWorld;
  tool->GetMatrixTransformToWorld(toWorld);
  for (int i = 0; i < 3; ++i) tipRAS[i] = toWorld->GetElement(i, 3);
}

vtkStaticCellLocator* vtkRPNavigationLogic::LocatorFor(vtkRPModelNode* model) {
  vtkPolyData* mesh = model->GetPolyData();
  CachedLocator& cached = this->Locators[model->GetID()];
  // Rebuild only when the mesh changed (a locator over a bone takes milliseconds, a query µs).
  if (!cached.Locator || cached.PolyDataTime != mesh->GetMTime()) {
    cached.Locator = vtkSmartPointer<vtkStaticCellLocator>::New();
    cached.Locator->SetDataSet(mesh);
    cached.Locator->BuildLocator();
    cached.PolyDataTime = mesh->GetMTime();
  }
  return cached.Locator;
}

vtkRPNavigationLogic::Result vtkRPNavigationLogic::Update() {
  Result result;
  if (this->Updating || !this->Scene) return result;
  auto* tool = vtkRPTransformableNode::SafeDownCast(this->Scene->GetNodeByID(this->ToolNodeID));
  if (!tool) {
    this->Last = result;
    this->LastReadout = rp::GuidanceReadout{};
    return result;
  }
  this->Updating = true;
  {
    const int previous = tool->StartModify();
    this->UpdateReadout(tool);
    tool->EndModify(previous);
  }
  GetTipRAS(tool, result.TipRAS);
  double best = VTK_DOUBLE_MAX;
  for (const auto& id : this->TargetModelNodeIDs) {
    auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(id));
    if (!model || !model->GetPolyData() || model->GetPolyData()->GetNumberOfCells() == 0) continue;
    // Query in the model's own frame (it may sit under a transform).
    vtkNew<vtkMatrix4x4> modelToWorld, worldToModel;
    model->GetMatrixTransformToWorld(modelToWorld);
    vtkMatrix4x4::Invert(modelToWorld, worldToModel);
    const double tipWorld[4] = {result.TipRAS[0], result.TipRAS[1], result.TipRAS[2], 1};
    double tipModel[4];
    worldToModel->MultiplyPoint(tipWorld, tipModel);
    double closest[3], distance2 = 0;
    vtkIdType cellId = -1;
    int subId = 0;
    vtkNew<vtkGenericCell> cell;
    this->LocatorFor(model)->FindClosestPoint(tipModel, closest, cell, cellId, subId, distance2);
    if (cellId < 0) continue;
    double distance = std::sqrt(distance2);
    // Sign from the closest facet's outward normal (meshes from SegmentationToMesh are closed
    // and consistently oriented): inside when the tip is behind the facet.
    double normal[3];
    model->GetPolyData()->GetCell(cellId, cell);  // the locator leaves the last cell it tried in `cell`
    vtkPoints* points = cell->GetPoints();
    if (points->GetNumberOfPoints() >= 3) {
      double p0[3], p1[3], p2[3];  // GetPoint(id) returns a shared buffer: copy each point
      points->GetPoint(0, p0);
      points->GetPoint(1, p1);
      points->GetPoint(2, p2);
      vtkTriangle::ComputeNormal(p0, p1, p2, normal);
      const double d[3] = {tipModel[0] - closest[0], tipModel[1] - closest[1], tipModel[2] - closest[2]};
      if (d[0] * normal[0] + d[1] * normal[1] + d[2] * normal[2] < 0) distance = -distance;
    }
    if (std::abs(distance) < std::abs(best)) {
      best = distance;
      result.ClosestModelID = id;
      const double c[4] = {closest[0], closest[1], closest[2], 1};
      double cw[4];
      modelToWorld->MultiplyPoint(c, cw);
      for (int i = 0; i < 3; ++i) result.ClosestPointRAS[i] = cw[i];
    }
  }
  if (!result.ClosestModelID.empty()) {
    result.Valid = true;
    result.DistanceMM = best;
    result.Warning = best < this->WarningDistance;  // inside counts as under the threshold
    const int previous = tool->StartModify();
    tool->SetAttribute("Navigation.DistanceMM", std::to_string(result.DistanceMM));
    tool->SetAttribute("Navigation.ClosestModel", result.ClosestModelID);
    std::ostringstream p;
    p << result.ClosestPointRAS[0] << " " << result.ClosestPointRAS[1] << " " << result.ClosestPointRAS[2];
    tool->SetAttribute("Navigation.ClosestPointRAS", p.str());
    tool->SetAttribute("Navigation.Warning", result.Warning ? "1" : "0");
    tool->EndModify(previous);
  }
  this->Last = result;
  this->Updating = false;
  return result;
}
