// vtkRPPlanningLogic: the entry region, the proposal and its risk map, cut planes, screw models.
#include <algorithm>
#include <cmath>

#include <vtkCleanPolyData.h>
#include <vtkClipPolyData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkImageThreshold.h>
#include <vtkLinearSubdivisionFilter.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSphere.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include "rpLabelmapToMesh.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpScrewMesh.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"

namespace {

constexpr size_t MaxCandidates = 250000;

// Mean edge length of a triangle mesh's polygons.
double MeanEdge(vtkPolyData* mesh) {
  double sum = 0;
  long count = 0;
  rp::ForEachTriangle(mesh, [&](const vtkIdType*, const double* a, const double* b, const double* c, const double*) {
    sum += std::sqrt(vtkMath::Distance2BetweenPoints(a, b)) + std::sqrt(vtkMath::Distance2BetweenPoints(b, c)) +
           std::sqrt(vtkMath::Distance2BetweenPoints(c, a));
    count += 3;
  });
  return count ? sum / count : 0;
}

}  // namespace

bool vtkRPPlanningLogic::SetEntryRegion(vtkPolyData* regionWorld, const ProposalOptions& options, std::string& error) {
  if (!regionWorld || regionWorld->GetNumberOfPolys() == 0) {
    error = "the entry region has no surface";
    return false;
  }
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(regionWorld);
  vtkSmartPointer<vtkAlgorithm> last = triangles.GetPointer();
  if (options.SphereRadiusMm > 0) {  // only the region within the sphere
    vtkNew<vtkSphere> sphere;
    sphere->SetCenter(const_cast<double*>(options.SphereCenter));
    sphere->SetRadius(options.SphereRadiusMm);
    auto clip = vtkSmartPointer<vtkClipPolyData>::New();
    clip->SetInputConnection(last->GetOutputPort());
    clip->SetClipFunction(sphere);
    clip->InsideOutOn();
    last = clip;
  }
  last->Update();
  auto region = vtkSmartPointer<vtkPolyData>::New();
  region->DeepCopy(vtkPolyData::SafeDownCast(last->GetOutputDataObject(0)));
  if (region->GetNumberOfPolys() == 0) {
    error = "the entry region has no surface within the sphere of " + std::to_string(options.SphereRadiusMm) + " mm";
    return false;
  }
  // Refine until the mean edge is at most the spacing asked: the points are the candidates.
  const double spacing = std::max(0.05, options.SpacingMm);
  for (double edge = MeanEdge(region); edge > 1.5 * spacing && region->GetNumberOfPoints() * 4 < static_cast<vtkIdType>(MaxCandidates);
       edge /= 2) {
    vtkNew<vtkLinearSubdivisionFilter> subdivide;
    subdivide->SetInputData(region);
    subdivide->SetNumberOfSubdivisions(1);
    subdivide->Update();
    region->DeepCopy(subdivide->GetOutput());
  }
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputData(region);
  clean->Update();
  region->DeepCopy(clean->GetOutput());
  this->Region = region;
  this->Candidates.clear();
  for (vtkIdType i = 0; i < region->GetNumberOfPoints(); ++i) {
    double p[3];
    region->GetPoint(i, p);
    this->Candidates.push_back({p[0], p[1], p[2]});
  }
  this->CandidateOrder = rp::SpatialOrder(this->Candidates);
  this->CandidateSpacing = rp::MedianSpacing(this->Candidates);
  return true;
}

bool vtkRPPlanningLogic::SetEntryRegion(vtkRPModelNode* region, const ProposalOptions& options, std::string& error) {
  if (!region) {
    error = "no entry region";
    return false;
  }
  vtkNew<vtkMatrix4x4> toWorld;
  region->GetMatrixTransformToWorld(toWorld);
  rp::TriangleMesh mesh;
  if (!rp::PolyDataToTriangleMesh(region->GetPolyData(), toWorld, mesh, error)) {
    error = "the entry region '" + region->GetName() + "' has no surface: " + error;
    return false;
  }
  return this->SetEntryRegion(rp::TriangleMeshToPolyData(mesh), options, error);
}

bool vtkRPPlanningLogic::SetEntryRegionFromSegment(vtkRPSegmentationNode* segmentation, const std::string& reference,
                                                   const ProposalOptions& options, std::string& error) {
  const rp::Segment* segment = segmentation ? segmentation->FindSegment(reference) : nullptr;
  if (!segment) {
    error = "no segment '" + reference + "' for the entry region";
    return false;
  }
  const auto surface = this->SegmentSurface(segmentation, *segment, error);
  if (!surface) {
    error = "the entry region '" + segment->Name + "' has no surface: " + error;
    return false;
  }
  return this->SetEntryRegion(rp::TriangleMeshToPolyData(*surface), options, error);
}

bool vtkRPPlanningLogic::Propose(const double targetRAS[3], const ProposalOptions& options, rp::ProposalResult& result,
                                 std::string& error) {
  if (this->Candidates.empty()) {
    error = "no entry region set";
    return false;
  }
  const rp::TissueModel& tissue = this->Inputs.Tissue();
  const rp::Vec3 target{targetRAS[0], targetRAS[1], targetRAS[2]};
  if ((tissue.HasCT() || tissue.HasLabels()) && !tissue.Contains(target)) {
    error = "the target lies outside the volume";
    return false;
  }
  std::vector<rp::StructureAtRiskSnapshot> structures;
  if (!this->GetStructuresAtRiskSnapshot(structures, error)) return false;
  for (const auto& s : structures)
    if (s.Signed && s.Signed->SignedDistance(target) < 0) {
      error = "the target lies inside the structure at risk '" + s.Name + "'";
      return false;
    }
  rp::ProposalRequest request;
  request.Target = target;
  request.ToolDiameterMm = options.ToolDiameterMm;
  request.Candidates = this->Candidates;
  request.StayInBone = options.StayInBone;
  request.Best = options.Best;
  request.Threads = options.Threads;
  request.Order = &this->CandidateOrder;
  request.SpacingMm = this->CandidateSpacing;
  result = rp::ProposeTrajectory(request, structures, &tissue);
  error = result.Error;
  return result.Error.empty();
}

vtkSmartPointer<vtkPolyData> vtkRPPlanningLogic::RiskMapPolyData(const rp::ProposalResult& result) const {
  auto map = vtkSmartPointer<vtkPolyData>::New();
  if (!this->Region || result.Scores.size() != static_cast<size_t>(this->Region->GetNumberOfPoints())) return map;
  map->DeepCopy(this->Region);
  vtkNew<vtkFloatArray> clearance, slack;
  clearance->SetName("clearanceMm");
  slack->SetName("slackMm");
  vtkNew<vtkUnsignedCharArray> usable;
  usable->SetName("usable");  // 1: a valid entry that keeps the tool in bone when asked
  for (const rp::CandidateScore& s : result.Scores) {
    clearance->InsertNextValue(std::isfinite(s.ClearanceMm) ? s.ClearanceMm : 1e6f);
    slack->InsertNextValue(std::isfinite(s.SlackMm) ? s.SlackMm : 1e6f);
    usable->InsertNextValue(s.Valid && s.InBone ? 1 : 0);
  }
  map->GetPointData()->AddArray(clearance);
  map->GetPointData()->AddArray(slack);
  map->GetPointData()->AddArray(usable);
  map->GetPointData()->SetActiveScalars("clearanceMm");
  return map;
}

vtkRPModelNode* vtkRPPlanningLogic::UpdateRiskMap(const rp::ProposalResult& result, const std::string& name) {
  if (!this->Scene) return nullptr;
  auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetFirstNodeByName(name));
  if (!model) {
    vtkNew<vtkRPModelNode> created;
    created->SetName(name);
    // Not under "RoboPlan.": that prefix is our fields' in MRML (rpMrmlNames.h), and a plain
    // attribute there would not survive a .mrml/.mrb.
    created->SetAttribute("Planning.riskMap", "clearanceMm");
    model = vtkRPModelNode::SafeDownCast(this->Scene->AddNode(created));
  }
  model->SetPolyData(this->RiskMapPolyData(result));
  return model;
}

vtkRPModelNode* vtkRPPlanningLogic::UpdateScrewModel(vtkRPScrewNode* screw) {
  rp::TrajectorySnapshot plan;
  if (!this->Scene || !TrajectoryOf(screw, plan) || !(plan.LengthMm() > 0)) return nullptr;
  auto* model = vtkRPModelNode::SafeDownCast(screw->GetNodeReference(vtkRPScrewNode::ScrewModelRole()));
  if (!model) {
    vtkNew<vtkRPModelNode> created;
    created->SetName(screw->GetName() + " model");
    created->SetColor(screw->GetColor());
    model = vtkRPModelNode::SafeDownCast(this->Scene->AddNode(created));
    screw->SetNodeReferenceID(vtkRPScrewNode::ScrewModelRole(), model->GetID());
  }
  // The model holds world coordinates: it has no parent transform of its own.
  model->SetPolyData(rp::TriangleMeshToPolyData(rp::MakeScrewMesh(plan)));
  return model;
}

bool vtkRPPlanningLogic::BoneSurfaces(std::vector<std::pair<std::string, std::shared_ptr<const rp::TriangleMesh>>>& bones,
                                      std::string& error) {
  bones.clear();
  const rp::TissueModel& tissue = this->Inputs.Tissue();
  if (this->Segmentation) {
    for (const rp::LabelledTissue& t : tissue.Segments) {
      if (!t.IsBone) continue;
      const rp::Segment* segment = this->Segmentation->GetSegmentByLabel(t.Label);
      auto surface = segment ? this->SegmentSurface(this->Segmentation, *segment, error) : nullptr;
      if (!surface) return false;
      bones.push_back({t.Name, surface});
    }
    return true;
  }
  for (vtkRPNode* node : this->Scene ? this->Scene->GetNodesByClass("vtkRPModelNode") : std::vector<vtkRPNode*>{}) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (!rp::IsBoneTissue(this->GetMaterials(), model->GetTissueClass())) continue;
    auto mesh = std::make_shared<rp::TriangleMesh>();
    vtkNew<vtkMatrix4x4> toWorld;
    model->GetMatrixTransformToWorld(toWorld);
    if (!rp::PolyDataToTriangleMesh(model->GetPolyData(), toWorld, *mesh, error)) return false;
    bones.push_back({model->GetName(), mesh});
  }
  if (!bones.empty() || !this->CT) return true;
  return this->ThresholdBoneSurface(bones, error);
}

bool vtkRPPlanningLogic::ComputeCut(vtkRPCutPlaneNode* plane, std::vector<BoneCut>& cuts, std::string& error) {
  if (!plane || !plane->IsComplete()) {
    error = plane ? "cut plane '" + plane->GetName() + "' is not placed" : "no cut plane";
    return false;
  }
  if (this->CT && !CheckPlannedOn(plane, this->CT, error)) return false;
  std::vector<std::pair<std::string, std::shared_ptr<const rp::TriangleMesh>>> bones;
  if (!this->BoneSurfaces(bones, error)) return false;
  if (bones.empty()) {
    error = "no bone to cut: give a segmentation with bone segments, bone models or a CT";
    return false;
  }
  double origin[3], normal[3];
  plane->GetOriginWorld(origin);
  plane->GetNormalWorld(normal);
  cuts.clear();
  for (const auto& [name, mesh] : bones)
    cuts.push_back({name, rp::CutBone(*mesh, {origin[0], origin[1], origin[2]}, {normal[0], normal[1], normal[2]})});
  return true;
}

// Without a segmentation or bone models: the CT's bone (at or above the bone threshold) meshed
// as one closed surface, as the segment models are.
bool vtkRPPlanningLogic::ThresholdBoneSurface(
    std::vector<std::pair<std::string, std::shared_ptr<const rp::TriangleMesh>>>& bones, std::string& error) {
  vtkImageData* image = this->CT->GetImageData();
  const double threshold = this->Inputs.Tissue().BoneThresholdHU;
  vtkNew<vtkImageThreshold> mask;
  mask->SetInputData(image);
  mask->ThresholdByUpper(threshold);
  mask->SetInValue(1);
  mask->SetOutValue(0);
  mask->SetOutputScalarTypeToUnsignedChar();
  mask->Update();
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld;
  this->CT->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, this->CT->GetIJKToRASMatrix(), ijkToWorld);
  vtkNew<vtkPolyData> surface;
  rp::MeshStats stats;
  auto mesh = std::make_shared<rp::TriangleMesh>();
  if (!rp::LabelmapToMesh(mask->GetOutput(), ijkToWorld, 1, rp::MeshOptions{}, surface, stats, error) ||
      !rp::PolyDataToTriangleMesh(surface, nullptr, *mesh, error)) {
    error = "the CT has no bone at or above " + std::to_string(static_cast<int>(threshold)) + " HU: " + error;
    return false;
  }
  bones.push_back({"bone (CT at or above " + std::to_string(static_cast<int>(threshold)) + " HU)", mesh});
  return true;
}
