#include "vtkRPPlanningLogic.h"

#include <cstdio>
#include <sstream>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "rpLabelmapToMesh.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpPropertyText.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

vtkStandardNewMacro(vtkRPPlanningLogic);

namespace {

rp::Vec3 ToVec3(const double v[3]) { return {v[0], v[1], v[2]}; }

std::string FormatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", v);
  return text;
}

std::string FormatPoint(const rp::Vec3& p) {
  return "R " + FormatNumber(p.x) + ", A " + FormatNumber(p.y) + ", S " + FormatNumber(p.z) + " mm";
}

// Two identities' grids ("grid DxDxD ijkToRAS 12 numbers"): same dimensions, matrices within 1e-4.
bool SameGrid(const std::string& a, const std::string& b) {
  auto parse = [](const std::string& identity, std::string& dims, std::vector<double>& m) {
    const size_t at = identity.find("grid ");
    if (at == std::string::npos) return false;
    std::istringstream in(identity.substr(at + 5));
    std::string word, numbers;
    in >> dims >> word;
    std::getline(in, numbers);
    return word == "ijkToRAS" && rp::ParsePropertyNumbers(numbers, m, 12);
  };
  std::string da, db;
  std::vector<double> ma, mb;
  if (!parse(a, da, ma) || !parse(b, db, mb) || da != db) return false;
  for (size_t i = 0; i < 12; ++i)
    if (std::fabs(ma[i] - mb[i]) > 1e-4) return false;
  return true;
}

// Modification time of a node's parent chain (a moved parent moves the structure).
unsigned long TransformTime(vtkRPTransformableNode* node) {
  unsigned long time = 0;
  for (vtkRPLinearTransformNode* parent = node->GetParentTransformNode(); parent; parent = parent->GetParentTransformNode())
    time = std::max<unsigned long>(time, parent->GetMTime());
  return time;
}

bool MeshSegment(vtkRPSegmentationNode* segmentation, const rp::Segment& segment, rp::TriangleMesh& mesh,
                 std::string& error) {
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld;
  segmentation->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, segmentation->GetIJKToRASMatrix(), ijkToWorld);
  vtkNew<vtkPolyData> surface;
  rp::MeshStats stats;
  if (!segmentation->GetImageData() ||
      !rp::LabelmapToMesh(segmentation->GetImageData(), ijkToWorld, segment.LabelValue, rp::MeshOptions{}, surface,
                          stats, error))
    return false;
  return rp::PolyDataToTriangleMesh(surface, nullptr, mesh, error);
}

}  // namespace

bool vtkRPPlanningLogic::TrajectoryOf(vtkRPTrajectoryNode* trajectory, rp::TrajectorySnapshot& t) {
  if (!trajectory || !trajectory->IsComplete()) return false;
  t = rp::TrajectorySnapshot{};
  t.NodeID = trajectory->GetID();
  t.Name = trajectory->GetName();
  double entry[3], target[3];
  trajectory->GetEntryWorld(entry);
  trajectory->GetTargetWorld(target);
  t.Entry = ToVec3(entry);
  t.Target = ToVec3(target);
  t.ToolDiameterMm = trajectory->GetToolDiameterMm();
  if (auto* screw = vtkRPScrewNode::SafeDownCast(trajectory)) {
    t.IsScrew = true;
    t.ScrewDiameterMm = screw->GetScrewDiameterMm();
    t.ScrewLengthMm = screw->GetScrewLengthMm();
    t.HeadDiameterMm = screw->GetHeadDiameterMm();
    t.HeadLengthMm = screw->GetHeadLengthMm();
  }
  return true;
}

void vtkRPPlanningLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << this->Scene << "\n"
     << indent << "Meshed segments cached: " << this->SegmentSurfaces.size() << "\n";
}

std::vector<vtkRPPlanningLogic::StructureAtRisk> vtkRPPlanningLogic::GetStructuresAtRisk() const {
  std::vector<StructureAtRisk> structures;
  if (!this->Scene) return structures;
  for (vtkRPNode* node : this->Scene->GetNodes()) {
    if (auto* model = vtkRPModelNode::SafeDownCast(node)) {
      if (model->GetProtection().Protected)
        structures.push_back({node, "", node->GetName(), model->GetProtection().SafetyMarginMm});
    } else if (auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node)) {
      for (const auto& segment : segmentation->GetSegments())
        if (segment.Protection.Protected)
          structures.push_back({node, segment.ID, segment.Name, segment.Protection.SafetyMarginMm});
    }
  }
  return structures;
}

std::shared_ptr<const rp::TriangleMesh> vtkRPPlanningLogic::SegmentSurface(vtkRPSegmentationNode* segmentation,
                                                                          const rp::Segment& segment, std::string& error) {
  CachedSurface& cached = this->SegmentSurfaces[{segmentation->GetID(), segment.ID}];
  const unsigned long nodeTime = segmentation->GetMTime(), transformTime = TransformTime(segmentation);
  if (cached.Surface && cached.NodeTime == nodeTime && cached.TransformTime == transformTime) return cached.Surface;
  auto mesh = std::make_shared<rp::TriangleMesh>();
  if (!MeshSegment(segmentation, segment, *mesh, error)) return nullptr;
  mesh->ComputeNormals();
  cached = {nodeTime, transformTime, mesh};
  return mesh;
}

std::shared_ptr<const rp::TriangleMesh> vtkRPPlanningLogic::GetStructureSurface(const StructureAtRisk& structure,
                                                                               std::string& error) {
  if (auto* model = vtkRPModelNode::SafeDownCast(structure.Node)) {
    auto mesh = std::make_shared<rp::TriangleMesh>();
    vtkNew<vtkMatrix4x4> toWorld;
    model->GetMatrixTransformToWorld(toWorld);
    if (!rp::PolyDataToTriangleMesh(model->GetPolyData(), toWorld, *mesh, error)) {
      error = "structure at risk '" + structure.Name + "' (model) has no surface: " + error;
      return nullptr;
    }
    mesh->ComputeNormals();
    return mesh;
  }
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(structure.Node);
  const rp::Segment* segment = segmentation ? segmentation->GetSegmentByID(structure.SegmentID) : nullptr;
  if (!segment) {
    error = "structure at risk '" + structure.Name + "' is neither a model nor a segment of the scene";
    return nullptr;
  }
  auto surface = this->SegmentSurface(segmentation, *segment, error);
  if (!surface)
    error = "structure at risk '" + structure.Name + "' (segment of '" + segmentation->GetName() +
            "') has no surface: " + error;
  return surface;
}

bool vtkRPPlanningLogic::GetStructuresAtRiskSnapshot(std::vector<rp::StructureAtRiskSnapshot>& structures, std::string& error) {
  // Rebuilt only when a structure, its node or a transform above it changed (dragging a plan
  // re-measures against the same trees).
  const std::vector<StructureAtRisk> current = this->GetStructuresAtRisk();
  unsigned long time = current.size();
  for (const StructureAtRisk& s : current) {
    time = std::max<unsigned long>(time, s.Node->GetMTime());
    if (auto* t = vtkRPTransformableNode::SafeDownCast(s.Node)) time = std::max(time, TransformTime(t));
  }
  if (time == this->StructureCacheTime && current.size() == this->StructureCache.size()) {
    structures = this->StructureCache;
    return true;
  }
  std::vector<rp::StructureAtRiskSnapshot> built;
  for (const StructureAtRisk& structure : current) {
    rp::StructureAtRiskSnapshot s;
    s.NodeID = structure.Node->GetID();
    s.SegmentID = structure.SegmentID;
    s.Name = structure.Name;
    s.SafetyMarginMm = structure.SafetyMarginMm;
    s.Surface = this->GetStructureSurface(structure, error);
    if (!s.Surface) return false;
    auto tree = std::make_shared<rp::BVH>();
    tree->Build(*s.Surface);
    s.Tree = tree;
    auto signedDistance = std::make_shared<rp::MeshSignedDistance>();
    std::string openSurface;
    if (signedDistance->Build(*s.Surface, openSurface)) s.Signed = signedDistance;
    built.push_back(std::move(s));
  }
  this->StructureCache = built;
  this->StructureCacheTime = time;
  structures = std::move(built);
  return true;
}

bool vtkRPPlanningLogic::AddStructures(rp::PlanSnapshot& plan, std::string& error) {
  return this->GetStructuresAtRiskSnapshot(plan.StructuresAtRisk, error);
}

std::shared_ptr<const rp::PlanSnapshot> vtkRPPlanningLogic::MakePlanSnapshot(std::string& error) {
  if (!this->Scene) {
    error = "planning logic has no scene";
    return nullptr;
  }
  auto plan = std::make_shared<rp::PlanSnapshot>();
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPTrajectoryNode")) {
    rp::TrajectorySnapshot t;
    if (!TrajectoryOf(vtkRPTrajectoryNode::SafeDownCast(node), t)) continue;
    if (!(t.LengthMm() > 0)) {
      error = "trajectory '" + t.Name + "' has zero length: its entry and target are the same point";
      return nullptr;
    }
    plan->Trajectories.push_back(t);
  }
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPCutPlaneNode")) {
    auto* plane = vtkRPCutPlaneNode::SafeDownCast(node);
    if (!plane->IsComplete()) continue;
    rp::CutPlaneSnapshot p;
    p.NodeID = node->GetID();
    p.Name = node->GetName();
    double origin[3], normal[3], xAxis[3];
    plane->GetOriginWorld(origin);
    plane->GetNormalWorld(normal);
    plane->GetXAxisWorld(xAxis);
    p.Origin = ToVec3(origin);
    p.Normal = ToVec3(normal);
    p.XAxis = ToVec3(xAxis);
    p.SizeMm[0] = plane->GetSize()[0];
    p.SizeMm[1] = plane->GetSize()[1];
    plan->Planes.push_back(p);
  }
  if (!this->AddStructures(*plan, error)) return nullptr;
  return plan;
}

std::shared_ptr<const rp::FixtureSet> vtkRPPlanningLogic::MakePlanFixtures(rp::PlanFixtureChoice choice, std::string& error) {
  const std::shared_ptr<const rp::PlanSnapshot> plan = this->MakePlanSnapshot(error);
  if (!plan) return nullptr;
  if (choice.Surface && !choice.SurfaceModelNode.empty()) {
    vtkRPNode* node = this->Scene->GetNodeByID(choice.SurfaceModelNode);
    if (!node) node = this->Scene->GetFirstNodeByName(choice.SurfaceModelNode);
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (!model) {
      error = "the scene has no model '" + choice.SurfaceModelNode + "' for the surface constraint";
      return nullptr;
    }
    if (!model->GetPolyData() || model->GetPolyData()->GetNumberOfPolys() == 0) {
      error = "model '" + model->GetName() + "' has no surface for the surface constraint";
      return nullptr;
    }
    choice.SurfaceModel = this->GetStructureSurface({model, "", model->GetName(), 0}, error);
    if (!choice.SurfaceModel) return nullptr;
    choice.SurfaceModelNode = model->GetName().empty() ? model->GetID() : model->GetName();
  }
  return rp::BuildPlanFixtures(*plan, choice, error);
}

const rp::MaterialTable& vtkRPPlanningLogic::GetMaterials() {
  if (this->Materials.Empty()) {
    std::string error;
    if (!rp::LoadMaterialTable(this->Materials, error)) this->Materials = rp::MaterialTable::Defaults();
  }
  return this->Materials;
}

bool vtkRPPlanningLogic::SetPatientData(vtkRPScalarVolumeNode* ct, vtkRPSegmentationNode* segmentation,
                                        std::string& error, const std::vector<std::string>& boneSegments) {
  rp::PlanningInputs inputs;
  if (!inputs.Set(ct, segmentation, this->GetMaterials(), error, boneSegments)) return false;
  this->Inputs = std::move(inputs);
  this->CT = ct;
  this->Segmentation = segmentation;
  return true;
}

// The bad inputs a plan's figures refuse, each named.
bool vtkRPPlanningLogic::CheckTrajectory(vtkRPTrajectoryNode* node, const rp::TrajectorySnapshot& plan,
                                         const std::vector<rp::StructureAtRiskSnapshot>& structures, std::string& error) {
  const std::string name = "'" + plan.Name + "'";
  if (!(plan.LengthMm() > 1e-6)) {
    error = "trajectory " + name + " has zero length: its entry and target are the same point";
    return false;
  }
  if (this->CT && !CheckPlannedOn(node, this->CT, error)) return false;
  const rp::TissueModel& tissue = this->Inputs.Tissue();
  if ((tissue.HasCT() || tissue.HasLabels()) && !tissue.Contains(plan.Target)) {
    error = "the target of " + name + " lies outside the volume (" + FormatPoint(plan.Target) + ")";
    return false;
  }
  for (const auto& s : structures)
    if (s.Signed && s.Signed->SignedDistance(plan.Entry) < 0) {
      error = "the entry of " + name + " lies inside the structure at risk '" + s.Name + "'";
      return false;
    }
  if (plan.IsScrew && (tissue.HasCT() || tissue.HasLabels())) return this->CheckScrewFits(plan, error);
  return true;
}

// A screw longer than the bone along its axis: its shaft would stand out of it.
bool vtkRPPlanningLogic::CheckScrewFits(const rp::TrajectorySnapshot& plan, std::string& error) {
  const rp::TissueModel& tissue = this->Inputs.Tissue();
  rp::ToolSpan line = rp::ToolSpanOf(plan);
  const double reach = plan.LengthMm() + plan.ScrewLengthMm + 50;  // the whole bone along the line
  const auto bone = rp::BoneAlongAxis(line, tissue, line.StartDepthMm - reach, plan.LengthMm() + 50);
  // The bone interval holding the screw's tip (the target), or the last one before it.
  const rp::DepthInterval* holding = nullptr;
  for (const auto& b : bone)
    if (b.FromMm <= plan.LengthMm() + 1e-6) holding = &b;
  const double boneLength = holding ? holding->ToMm - holding->FromMm : 0;
  if (plan.ScrewLengthMm > boneLength + 1e-6) {
    error = "screw '" + plan.Name + "' (" + FormatNumber(plan.ScrewLengthMm) + " mm) is longer than the bone along its axis (" +
            (holding ? FormatNumber(boneLength) + " mm" : std::string("none at its tip")) + "): it would stand out of the bone";
    return false;
  }
  return true;
}

bool vtkRPPlanningLogic::ComputeFigures(vtkRPTrajectoryNode* node, rp::TrajectoryFigures& figures, std::string& error) {
  rp::TrajectorySnapshot plan;
  if (!TrajectoryOf(node, plan)) {
    error = node ? "trajectory '" + node->GetName() + "' is not placed (it needs an entry and a target)" : "no trajectory";
    return false;
  }
  std::vector<rp::StructureAtRiskSnapshot> structures;
  if (!this->GetStructuresAtRiskSnapshot(structures, error) || !this->CheckTrajectory(node, plan, structures, error)) return false;
  figures = rp::ComputeTrajectoryFigures(plan, this->Inputs.Tissue(), structures);
  return true;
}

std::string vtkRPPlanningLogic::VolumeIdentity(vtkRPScalarVolumeNode* volume) {
  if (!volume || !volume->GetImageData()) return "";
  std::string identity;
  for (const char* key : {"DICOM.SeriesInstanceUID", "DICOM.FrameOfReferenceUID"})
    if (volume->HasAttribute(key)) identity += std::string(key + 6) + " " + volume->GetAttribute(key) + "; ";
  int dims[3];
  volume->GetImageData()->GetDimensions(dims);
  double m[16];
  vtkMatrix4x4::DeepCopy(m, volume->GetIJKToRASMatrix());
  const double grid[12] = {m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]};
  identity += "grid " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
              " ijkToRAS " + rp::FormatPropertyNumbers(grid, 12);
  return identity;
}

bool vtkRPPlanningLogic::CheckPlannedOn(vtkRPPlanNode* plan, vtkRPScalarVolumeNode* volume, std::string& error) {
  if (!plan || !volume || plan->GetPlannedOn().empty()) return true;
  const std::string current = VolumeIdentity(volume), planned = plan->GetPlannedOn();
  if (current == planned) return true;
  // The same DICOM series and frame of reference is the same patient's CT, whatever grid it was
  // resampled to; otherwise the grid must match to 1e-4 mm.
  auto field = [](const std::string& identity, const std::string& key) {
    const size_t at = identity.find(key + " ");
    return at == std::string::npos ? std::string() : identity.substr(at + key.size() + 1, identity.find(';', at) - at - key.size() - 1);
  };
  for (const char* key : {"SeriesInstanceUID", "FrameOfReferenceUID"}) {
    const std::string a = field(planned, key), b = field(current, key);
    if (!a.empty() && !b.empty() && a != b) {
      error = "plan '" + plan->GetName() + "' was made on another patient's CT: its " + key + " is " + a + ", the CT '" +
              volume->GetName() + "' has " + b;
      return false;
    }
  }
  if (!field(planned, "SeriesInstanceUID").empty() && field(planned, "SeriesInstanceUID") == field(current, "SeriesInstanceUID"))
    return true;
  if (!SameGrid(planned, current)) {
    error = "plan '" + plan->GetName() + "' was made on another CT (" + planned.substr(planned.find("grid")) +
            ") than '" + volume->GetName() + "' (" + current.substr(current.find("grid")) + "): it is not this patient's plan";
    return false;
  }
  return true;
}
