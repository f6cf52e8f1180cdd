// Demo stage "Plan" (issue 37): the tibial tunnel of an ACL reconstruction and one screw planned
// as scene nodes through the Planning logic alone, as a planning lab would, before anything is
// drilled. Structures at risk: the fibula (its segment, 2 mm margin), a tube standing for the
// popliteal vessels behind the tibia (3 mm) and the PCL (1 mm). The tunnel's target is the ACL's
// tibial footprint (1 mm above it, into the joint); its entry is PROPOSED by the logic on a patch
// of the tibia's anteromedial face, where a tibial drill guide set at the usual angle comes out.
// The screw: a 6.5 mm cancellous screw across the proximal tibia, medial to lateral, 20 mm below
// the footprint, parallel to the joint, its tip 5 mm short of the lateral surface, placed where
// it keeps farthest from the tunnel and the structures at risk (a "raft" screw of medial plateau
// fixation). For each: the figures a surgeon checks (Planning README), the HU profile chart and a
// risk map. The nodes are saved with the scene (each a Slicer markups line, .mrk.json).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpDemoPlan.h"
#include "rpDemoStages.h"
#include "rpKneePhantom.h"
#include "rpMeshSignedDistance.h"
#include "rpPlanPictures.h"
#include "rpPlanReport.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpReport.h"
#include "rpStageRunner.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

const std::string PlanStage = "Plan";
constexpr double TunnelDiameter = 4.0;     // the 4 mm pilot of an 8–10 mm reamed tunnel
constexpr double ScrewDiameter = 6.5;      // cancellous screw
constexpr double ScrewPilotDiameter = 3.2; // its drill
constexpr double FibulaMargin = 2.0, VesselMargin = 3.0, PclMargin = 1.0;
constexpr double VesselRadius = 4.0, VesselClearance = 5.0;  // the bundle; clear of the posterior cortex

// The knee's own axes: lateral, anterior (the phantom's, in the axial plane) and superior.
struct KneeFrame {
  Vec3 L, A, S{0, 0, 1};
};
KneeFrame FrameOf(const DemoState& state) {
  KneeFrame f;
  f.L = Normalized(Vec3{state.KneeLateral[0], state.KneeLateral[1], state.KneeLateral[2]});
  f.A = Normalized(Vec3{state.KneeAnterior[0], state.KneeAnterior[1], state.KneeAnterior[2]});
  return f;
}

// The ACL's tibial footprint: the centroid of the ACL's surface within 1.5 mm of the tibia.
bool AclFootprint(const DemoState& state, Vec3& footprint) {
  const auto& model = *state.Phantom->Model;
  Vec3 sum{};
  int n = 0;
  for (const auto& p : model.SurfacePoints(KneeStructure::ACL, 6000)) {
    if (model.SignedDistance(KneeStructure::Tibia, p.data()) < 1.5) {
      sum += Vec3{p[0], p[1], p[2]};
      ++n;
    }
  }
  if (n < 10) return false;
  footprint = sum / n;
  return true;
}

// A closed tube (rings of `segments` points from a to b, each end closed by a fan): a manifold
// surface the Planning logic measures against and the fixtures wall off.
TriangleMesh TubeMesh(const Vec3& a, const Vec3& b, double radius, int segments, int rings) {
  const Vec3 u = Normalized(b - a);
  const Vec3 e1 = Normalized(Cross(u, std::fabs(u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0})), e2 = Cross(u, e1);
  TriangleMesh mesh;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * M_PI * s / segments;
      mesh.Points.push_back(a + (b - a) * (double(r) / (rings - 1)) + e1 * (radius * std::cos(angle)) +
                              e2 * (radius * std::sin(angle)));
    }
  const int32_t capA = int32_t(mesh.Points.size()), capB = capA + 1;
  mesh.Points.push_back(a);
  mesh.Points.push_back(b);
  auto at = [segments](int r, int s) { return int32_t(r * segments + (s % segments)); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      mesh.Triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1)});
      mesh.Triangles.push_back({at(r, s), at(r + 1, s + 1), at(r + 1, s)});
    }
  for (int s = 0; s < segments; ++s) {
    mesh.Triangles.push_back({capA, at(0, s + 1), at(0, s)});
    mesh.Triangles.push_back({capB, at(rings - 1, s), at(rings - 1, s + 1)});
  }
  return mesh;
}

vtkRPModelNode* AddStructureModel(DemoState& state, const std::string& name, vtkPolyData* surface, const double colour[3],
                                  double marginMm) {
  vtkNew<vtkRPModelNode> model;
  model->SetName(name);
  model->SetPolyData(surface);
  model->SetColor(colour[0], colour[1], colour[2]);
  model->SetTissueClass("");
  model->SetProtection({true, marginMm});
  state.Scene->AddNode(model);
  return model;
}

// The popliteal vessels' stand-in: a straight tube of 4 mm radius along the leg behind the tibia's
// posterior cortex (a little lateral of its middle, as the popliteal artery runs), from the joint
// line down 60 mm, 5 mm clear of the cortex's most posterior point over that span.
vtkRPModelNode* AddVesselStandIn(DemoState& state, const TriangleMesh& tibia, const Vec3& footprint, const KneeFrame& f,
                                 double& clearanceMm) {
  const double top = footprint.z + 5, bottom = footprint.z - 60;
  double lmin = HUGE_VAL, lmax = -HUGE_VAL;
  for (const Vec3& v : tibia.Points)
    if (v.z < top && v.z > bottom) lmin = std::min(lmin, Dot(v, f.L)), lmax = std::max(lmax, Dot(v, f.L));
  if (!(lmax > lmin)) throw std::runtime_error("the tibia's model does not reach below the joint");
  const double centreL = 0.5 * (lmin + lmax) + 5;
  double posterior = HUGE_VAL;
  for (const Vec3& v : tibia.Points)
    if (v.z < top && v.z > bottom && std::fabs(Dot(v, f.L) - centreL) < VesselRadius + VesselClearance)
      posterior = std::min(posterior, Dot(v, f.A));
  const double centreA = posterior - VesselClearance - VesselRadius;
  const Vec3 axis = f.L * centreL + f.A * centreA;
  const TriangleMesh tube = TubeMesh(Vec3{axis.x, axis.y, top}, Vec3{axis.x, axis.y, bottom}, VesselRadius, 24, 16);
  MeshSignedDistance distance;
  std::string error;
  if (!distance.Build(tube, error)) throw std::runtime_error("the vessels' stand-in: " + error);
  clearanceMm = HUGE_VAL;
  for (const Vec3& v : tibia.Points) clearanceMm = std::min(clearanceMm, distance.SignedDistance(v));
  const double red[3] = {0.8, 0.1, 0.15};
  return AddStructureModel(state, "Popliteal vessels (stand-in)", TriangleMeshToPolyData(tube), red, VesselMargin);
}

// Where the line from `inside` along `direction` leaves the closed surface (0.1 mm steps).
bool ExitAlong(const MeshSignedDistance& surface, const Vec3& inside, const Vec3& direction, Vec3& exit) {
  bool in = false;
  for (double t = 0; t < 120; t += 0.1) {
    const double d = surface.SignedDistance(inside + direction * t);
    in = in || d < 0;
    if (in && d > 0) {
      exit = inside + direction * t;
      return true;
    }
  }
  return false;
}

std::string Mm(double v, int digits = 1) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

std::string PointText(const Vec3& p) { return "(" + Mm(p.x) + ", " + Mm(p.y) + ", " + Mm(p.z) + ") RAS"; }

// The figures a surgeon checks before cutting, each beside its target where one applies.
void ReportFigures(DemoState& state, const std::string& plan, const TrajectoryFigures& f) {
  std::string bone;
  for (const DepthInterval& i : f.Bone) bone += (bone.empty() ? "" : ", ") + Mm(i.FromMm) + "–" + Mm(i.ToMm);
  state.Report->AddFigure(PlanStage, plan + ": length", f.LengthMm, "mm",
                          "tool " + Mm(f.ToolDiameterMm) + " mm; entry to target " + Mm(f.TrajectoryLengthMm) + " mm");
  state.Report->AddFigure(PlanStage, plan + ": length in bone", f.LengthInBoneMm, "mm", "in bone at depths " + bone + " mm");
  if (f.CorticalSurfaceShare >= 0)
    state.Report->AddFigure(PlanStage, plan + ": share of the tool's surface in cortical bone", 100 * f.CorticalSurfaceShare, "%",
                            "≥ the cortical CT number of materials.json");
  state.Report->AddFigureBelow(PlanStage, plan + ": cortical breach", f.Breach.Found ? f.Breach.BreachMm : 0.0, "mm", 2.0,
                               f.Breach.Found ? "Gertzbein–Robbins grade " + std::to_string(f.Breach.Grade) + " at " +
                                                    Mm(f.Breach.DepthMm) + " mm deep (target: grade 0–1)"
                                              : "none: Gertzbein–Robbins grade 0");
  for (const ClearanceFigure& c : f.Clearances)
    state.Report->AddFigureAbove(PlanStage, plan + ": clearance from " + c.Name, c.ClearanceMm, "mm", c.SafetyMarginMm,
                                 "closest at " + Mm(c.DepthMm) + " mm deep; the margin is " + Mm(c.SafetyMarginMm) + " mm");
}

// The plan's HU profile chart and its figures as JSON (the report's "plans").
nlohmann::json PlanRecord(DemoState& state, vtkRPPlanningLogic* logic, vtkRPTrajectoryNode* node,
                          const TrajectoryFigures& figures, const std::string& file) {
  TrajectorySnapshot snapshot;
  vtkRPPlanningLogic::TrajectoryOf(node, snapshot);
  nlohmann::json record = {{"name", node->GetName()}, {"nodeID", node->GetID()},
                           {"plan", TrajectoryJson(snapshot, node->GetIntendedTissue())},
                           {"figures", FiguresJson(figures, logic->GetInputs().Tissue())}};
  if (!CanDrawPicturesOrWarn(state, PlanStage, node->GetName() + " profile chart")) return record;
  std::string error;
  state.Report->AddPictureIf(
      WriteProfileChart((fs::path(state.Output) / file).string(), figures, logic->GetInputs().Tissue(), node->GetName(), error),
      PlanStage, file,
      node->GetName() + ": the CT numbers along the axis (and their range over the tool's cross-section) against depth "
                        "from the entry, with the cortical and cancellous ranges of materials.json.",
      error);
  return record;
}

void RiskMapPicture(DemoState& state, vtkRPPlanningLogic* logic, const ProposalResult& result, const Vec3& target,
                    const std::string& file, const std::string& caption) {
  if (!CanDrawPicturesOrWarn(state, PlanStage, file)) return;
  std::vector<StructureAtRiskSnapshot> structures;
  std::string error;
  const double t[3] = {target.x, target.y, target.z};
  const bool drawn = logic->GetStructuresAtRiskSnapshot(structures, error) &&
                     WriteRiskMapPicture((fs::path(state.Output) / file).string(), logic->RiskMapPolyData(result), structures,
                                         t, logic->GetCandidates(), result, error);
  state.Report->AddPictureIf(drawn, PlanStage, file, caption, error);
}

vtkRPTrajectoryNode* AddTrajectory(DemoState& state, vtkSmartPointer<vtkRPTrajectoryNode> node, const std::string& name,
                                   const Vec3& entry, const Vec3& target, double toolDiameter, const double colour[3]) {
  node->SetName(name);
  const double e[3] = {entry.x, entry.y, entry.z}, t[3] = {target.x, target.y, target.z};
  node->SetEntryAndTarget(e, t);
  node->SetToolDiameterMm(toolDiameter);
  node->SetIntendedTissue("bone");
  node->SetColor(colour[0], colour[1], colour[2]);
  node->SetPlannedOn(vtkRPPlanningLogic::VolumeIdentity(state.CT));
  return vtkRPTrajectoryNode::SafeDownCast(state.Scene->AddNode(node));
}

// ---- the tunnel: entry proposed on the anteromedial face, target the ACL footprint
vtkRPTrajectoryNode* PlanTunnel(DemoState& state, vtkRPPlanningLogic* logic, vtkRPModelNode* tibiaModel,
                                const MeshSignedDistance& tibia, const Vec3& footprint, const KneeFrame& f,
                                nlohmann::json& records) {
  // The patch: the tibia's surface within 8 mm (about 2 cm²) of where a tibial drill guide set
  // at the usual angle (up, back and lateral towards the footprint) comes out anteromedially.
  const Vec3 guide = Normalized(f.L * 12 - f.A * 18 + f.S * 28);
  Vec3 centre;
  if (!ExitAlong(tibia, footprint - f.S * 2.0, guide * -1.0, centre))
    throw std::runtime_error("the drill guide's line from the ACL footprint does not leave the tibia anteromedially");
  vtkRPPlanningLogic::ProposalOptions options;
  options.ToolDiameterMm = TunnelDiameter;
  options.SpacingMm = 1.0;
  options.SphereRadiusMm = 8;
  options.SphereCenter[0] = centre.x, options.SphereCenter[1] = centre.y, options.SphereCenter[2] = centre.z;
  options.Best = 3;
  const Vec3 target = footprint + f.S * 1.0;  // 1 mm into the joint: the tunnel opens on the footprint
  const double t[3] = {target.x, target.y, target.z};
  ProposalResult result;
  std::string error;
  if (!logic->SetEntryRegion(tibiaModel, options, error) || !logic->Propose(t, options, result, error))
    throw std::runtime_error("proposing the tunnel's entry: " + error);
  std::vector<StructureAtRiskSnapshot> structures;
  logic->GetStructuresAtRiskSnapshot(structures, error);
  for (size_t k = 0; k < result.Best.size(); ++k) {
    const CandidateScore& s = result.Scores[size_t(result.Best[k])];
    const std::string closest = s.Structure >= 0 && size_t(s.Structure) < structures.size() ? structures[size_t(s.Structure)].Name : "";
    state.Report->AddFigure(PlanStage, "tibial tunnel: proposed entry " + std::to_string(k + 1) + ", clearance", s.ClearanceMm, "mm",
                            PointText(logic->GetCandidates()[size_t(result.Best[k])]) + "; from " + closest + ", " +
                                Mm(s.SlackMm) + " mm beyond its margin" + (k == 0 ? " (planned)" : ""));
  }
  state.Report->AddFigure(PlanStage, "tibial tunnel: entries scored", double(result.Scores.size()), "",
                          "candidates " + Mm(result.SpacingMm, 2) + " mm apart on the anteromedial patch, scored in " +
                              Mm(1000 * result.Seconds) + " ms; entries of equal clearance: the shortest tunnel first");
  const double colour[3] = {0.1, 0.75, 0.2};
  vtkRPTrajectoryNode* node = AddTrajectory(state, vtkSmartPointer<vtkRPTrajectoryNode>::New(), "Tibial tunnel",
                                            logic->GetCandidates()[size_t(result.Best.front())], target, TunnelDiameter, colour);
  logic->UpdateRiskMap(result, "Tibial tunnel risk map");
  TrajectoryFigures figures;
  if (!logic->ComputeFigures(node, figures, error)) throw std::runtime_error("the tibial tunnel: " + error);
  ReportFigures(state, "tibial tunnel", figures);
  nlohmann::json record = PlanRecord(state, logic, node, figures, "plan-tibial-tunnel-profile.png");
  ProposalRequest request;
  request.Target = target;
  request.ToolDiameterMm = TunnelDiameter;
  request.Candidates = logic->GetCandidates();
  record["proposal"] = ProposalJson(request, result, structures);
  records.push_back(record);
  RiskMapPicture(state, logic, result, target, "plan-tibial-tunnel-risk-map.png",
                 "The tunnel's entry region on the tibia's anteromedial face coloured by the clearance a 4 mm tunnel to the "
                 "ACL footprint from each point keeps from the structures at risk (fibula, popliteal vessels' stand-in, "
                 "PCL), with the best entries. Where the colour is even, every entry's clearance is set near the "
                 "target (the PCL behind the footprint), the same for all: the shortest of the equal entries is planned.");
  return node;
}

// ---- the screw: medial to lateral below the plateau, clear of the tunnel and the structures
struct ScrewChoice {
  Vec3 Entry, Tip;  // on the medial surface; 5 mm short of the lateral surface
  double Score = -HUGE_VAL, TunnelGapMm = 0;
};

double DistanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(Dot(p - a, ab) / std::max(Norm2(ab), 1e-12), 0.0, 1.0);
  return Norm(p - (a + ab * t));
}

// Bone of the line from `from` to `to` as the Planning logic sees it (the longest interval).
bool BoneSpan(vtkRPPlanningLogic* logic, vtkRPTrajectoryNode* probe, const Vec3& from, const Vec3& to, Vec3& in, Vec3& out) {
  const double a[3] = {from.x, from.y, from.z}, b[3] = {to.x, to.y, to.z};
  probe->SetEntryAndTarget(a, b);
  TrajectoryFigures figures;
  std::string error;
  if (!logic->ComputeFigures(probe, figures, error) || figures.Bone.empty()) return false;
  const DepthInterval longest = *std::max_element(figures.Bone.begin(), figures.Bone.end(), [](const auto& x, const auto& y) {
    return x.ToMm - x.FromMm < y.ToMm - y.FromMm;
  });
  const Vec3 u = Normalized(to - from);
  in = from + u * longest.FromMm;
  out = from + u * longest.ToMm;
  return true;
}

ScrewChoice ChooseScrew(DemoState& state, vtkRPPlanningLogic* logic, const TriangleMesh& tibia, const Vec3& footprint,
                        const KneeFrame& f, const TrajectorySnapshot& tunnel) {
  const double level = footprint.z - 20;
  double lmin = HUGE_VAL, lmax = -HUGE_VAL, amin = HUGE_VAL, amax = -HUGE_VAL;
  for (const Vec3& v : tibia.Points)
    if (std::fabs(v.z - level) < 1.5) {
      lmin = std::min(lmin, Dot(v, f.L)), lmax = std::max(lmax, Dot(v, f.L));
      amin = std::min(amin, Dot(v, f.A)), amax = std::max(amax, Dot(v, f.A));
    }
  if (!(lmax > lmin)) throw std::runtime_error("the tibia's model has no section 20 mm below the ACL footprint");
  vtkNew<vtkRPTrajectoryNode> probe;
  probe->SetName("screw probe");
  probe->SetToolDiameterMm(ScrewDiameter);
  state.Scene->AddNode(probe);
  ScrewChoice best;
  for (double share : {0.3, 0.4, 0.5, 0.6, 0.7}) {  // from the front of the section to the back
    const Vec3 q = f.L * (0.5 * (lmin + lmax)) + f.A * (amax - share * (amax - amin));
    const Vec3 medial{q.x - f.L.x * (0.5 * (lmax - lmin) + 15), q.y - f.L.y * (0.5 * (lmax - lmin) + 15), level};
    const Vec3 lateral{q.x + f.L.x * (0.5 * (lmax - lmin) + 15), q.y + f.L.y * (0.5 * (lmax - lmin) + 15), level};
    ScrewChoice c;
    Vec3 out;
    if (!BoneSpan(logic, probe, medial, lateral, c.Entry, out) || Norm(out - c.Entry) < 40) continue;
    c.Tip = out - f.L * 5.0;
    // Its clearances as a tool of the screw's diameter from the medial surface to the tip.
    const double a[3] = {c.Entry.x, c.Entry.y, c.Entry.z}, b[3] = {c.Tip.x, c.Tip.y, c.Tip.z};
    probe->SetEntryAndTarget(a, b);
    TrajectoryFigures figures;
    std::string error;
    if (!logic->ComputeFigures(probe, figures, error)) continue;
    double slack = HUGE_VAL;
    for (const ClearanceFigure& k : figures.Clearances) slack = std::min(slack, k.ClearanceMm - k.SafetyMarginMm);
    c.TunnelGapMm = HUGE_VAL;
    for (double t = 0; t <= 1; t += 0.01)
      c.TunnelGapMm = std::min(c.TunnelGapMm, DistanceToSegment(c.Entry + (c.Tip - c.Entry) * t, tunnel.Entry, tunnel.Target));
    c.TunnelGapMm -= 0.5 * (ScrewDiameter + tunnel.ToolDiameterMm);
    c.Score = std::min(slack, c.TunnelGapMm - 2.0);  // 2 mm of bone between screw and tunnel
    if (c.Score > best.Score) best = c;
  }
  state.Scene->RemoveNode(probe);
  if (!std::isfinite(best.Score)) throw std::runtime_error("no medial-to-lateral screw line 20 mm below the footprint stays in the tibia");
  return best;
}

vtkRPScrewNode* PlanScrew(DemoState& state, vtkRPPlanningLogic* logic, const TriangleMesh& tibia, const Vec3& footprint,
                          const KneeFrame& f, const TrajectorySnapshot& tunnel, nlohmann::json& records) {
  ScrewChoice c = ChooseScrew(state, logic, tibia, footprint, f, tunnel);
  // The thread starts 1 mm under the medial surface (the head, with its washer, on the cortex);
  // screws come in 5 mm steps: the longest that ends short of the tip chosen.
  c.Entry += Normalized(c.Tip - c.Entry) * 1.0;
  const double length = 5.0 * std::floor(Norm(c.Tip - c.Entry) / 5.0);
  const Vec3 tip = c.Entry + Normalized(c.Tip - c.Entry) * length;
  auto screw = vtkSmartPointer<vtkRPScrewNode>::New();
  screw->SetScrewDiameterMm(ScrewDiameter);
  screw->SetScrewLengthMm(length);
  screw->SetHeadDiameterMm(8.0);
  screw->SetHeadLengthMm(4.0);
  const double colour[3] = {0.75, 0.75, 0.8};
  auto* node = vtkRPScrewNode::SafeDownCast(
      AddTrajectory(state, screw, "Medial plateau screw", c.Entry, tip, ScrewPilotDiameter, colour));
  logic->UpdateScrewModel(node);
  TrajectoryFigures figures;
  std::string error;
  if (!logic->ComputeFigures(node, figures, error)) throw std::runtime_error("the screw: " + error);
  state.Report->AddFigure(PlanStage, "screw: 6.5 mm cancellous screw, length", length, "mm",
                          "medial to lateral, 20 mm below the ACL footprint, parallel to the joint, tip " +
                              Mm(Norm(c.Tip - tip) + 5.0) + " mm short of the lateral surface; pilot drill 3.2 mm");
  state.Report->AddFigureAbove(PlanStage, "screw: bone between the screw and the tunnel", c.TunnelGapMm, "mm", 2.0,
                               "closest distance between the screw's and the tunnel's surfaces");
  ReportFigures(state, "screw", figures);
  nlohmann::json record = PlanRecord(state, logic, node, figures, "plan-screw-profile.png");
  // The medial face around its entry coloured by the clearance a screw to the same tip keeps.
  vtkRPPlanningLogic::ProposalOptions options;
  options.ToolDiameterMm = ScrewDiameter;
  options.SphereRadiusMm = 8;
  options.SphereCenter[0] = c.Entry.x, options.SphereCenter[1] = c.Entry.y, options.SphereCenter[2] = c.Entry.z;
  options.Best = 3;
  const double t[3] = {tip.x, tip.y, tip.z};
  ProposalResult result;
  auto* tibiaModel = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(state.DisplayModelIDOfSegment.at("tibia")));
  if (logic->SetEntryRegion(tibiaModel, options, error) && logic->Propose(t, options, result, error)) {
    std::vector<StructureAtRiskSnapshot> structures;
    logic->GetStructuresAtRiskSnapshot(structures, error);
    ProposalRequest request;
    request.Target = tip;
    request.ToolDiameterMm = ScrewDiameter;
    request.Candidates = logic->GetCandidates();
    record["proposal"] = ProposalJson(request, result, structures);
    logic->UpdateRiskMap(result, "Screw risk map");
    RiskMapPicture(state, logic, result, tip, "plan-screw-risk-map.png",
                   "The medial face around the screw's entry coloured by the clearance a 6.5 mm screw to the same tip "
                   "keeps from the structures at risk.");
  } else {
    state.Report->AddNote("The screw's risk map: " + error);
  }
  records.push_back(record);
  return node;
}

// The structures at risk: the fibula's segment, the vessels' stand-in, the PCL (the phantom's).
void FlagStructuresAtRisk(DemoState& state, const TriangleMesh& tibia, const Vec3& footprint, const KneeFrame& f) {
  Segment fibula = *state.Segmentation->GetSegmentByID("fibula");
  fibula.Protection = {true, FibulaMargin};
  state.Segmentation->SetSegment(fibula);
  double vesselClearance = 0;
  AddVesselStandIn(state, tibia, footprint, f, vesselClearance);
  state.Report->AddFigure(PlanStage, "popliteal vessels' stand-in: clear of the tibia", vesselClearance, "mm",
                          "a tube of 8 mm diameter behind the posterior cortex, from the joint line down 60 mm");
  const vtkSmartPointer<vtkPolyData> pcl = state.Phantom->Model->Surface(KneeStructure::PCL);
  if (!pcl) throw std::runtime_error("the phantom's anatomy has no PCL surface");
  const double red[3] = {0.85, 0.3, 0.3};
  AddStructureModel(state, "PCL", pcl, red, PclMargin);
}

}  // namespace

void PlanTunnelAndScrew(DemoState& state) {
  if (!state.HasGroundTruth()) {
    state.Report->AddNotScored(PlanStage, "tibial tunnel and screw plan",
                               "the tunnel's target is the ACL's tibial footprint, which a user's CT does not show (no "
                               "ligament is segmented); plan it with `roboplan plan propose` or the Planning panel");
    return;
  }
  const auto* tibiaSegment = state.Segmentation ? state.Segmentation->GetSegmentByID("tibia") : nullptr;
  const auto* fibulaSegment = state.Segmentation ? state.Segmentation->GetSegmentByID("fibula") : nullptr;
  const auto model = state.DisplayModelIDOfSegment.find("tibia");
  auto* tibiaModel = model == state.DisplayModelIDOfSegment.end()
                         ? nullptr
                         : vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(model->second));
  if (!tibiaSegment || !fibulaSegment || !tibiaModel) {
    state.Report->AddNotScored(PlanStage, "tibial tunnel and screw plan", "the tibia and the fibula were not both segmented and meshed");
    return;
  }
  TriangleMesh tibia;
  MeshSignedDistance tibiaDistance;
  std::string error;
  if (!PolyDataToTriangleMesh(tibiaModel->GetPolyData(), nullptr, tibia, error) || !tibiaDistance.Build(tibia, error))
    throw std::runtime_error("the tibia's model: " + error);
  Vec3 footprint;
  if (!AclFootprint(state, footprint)) throw std::runtime_error("the phantom's ACL does not reach the tibia");
  const KneeFrame frame = FrameOf(state);

  FlagStructuresAtRisk(state, tibia, footprint, frame);
  vtkNew<vtkRPPlanningLogic> logic;  // as the Planning panel and `roboplan plan`
  logic->SetScene(state.Scene);
  if (!logic->SetPatientData(state.CT, state.Segmentation, error)) throw std::runtime_error(error);
  state.Runner->Progress(0.2, "proposing the tunnel's entry");
  nlohmann::json records = nlohmann::json::array();
  vtkRPTrajectoryNode* tunnel = PlanTunnel(state, logic, tibiaModel, tibiaDistance, footprint, frame, records);
  state.TunnelPlanID = tunnel->GetID();
  state.Runner->Progress(0.6, "the screw");
  TrajectorySnapshot tunnelSnapshot;
  vtkRPPlanningLogic::TrajectoryOf(tunnel, tunnelSnapshot);
  state.ScrewPlanID = PlanScrew(state, logic, tibia, footprint, frame, tunnelSnapshot, records)->GetID();
  state.Report->SetJsonSection("plans", records.dump());
}

}  // namespace rp
