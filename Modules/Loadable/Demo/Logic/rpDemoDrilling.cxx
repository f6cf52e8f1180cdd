// Demo stage: the planned tibial tunnel of an ACL reconstruction (the Plan stage's trajectory
// node, rpDemoPlanning.cxx: the one definition of the tunnel) drilled with the burr at 1 kHz (the
// Drilling module, issue 15). The segmented tibia (this run's segmentation, cortical/trabecular
// from the CT's HU; its density follows the tibia's display model, the surface the user sees,
// not the labels meshed again) is drilled along the plan by the simulated device, from a start
// clear of the bone to the target; the plan's structures at risk (the PCL just behind the
// footprint, the fibula, the popliteal vessels' stand-in) are protected in the bone within their
// margins. The report gives the removed volume against the bone inside the planned tunnel, the
// closest approach to each structure at risk, the force along the path (chart), timings, and a
// picture of the tunnel. The drilled tibia is added to the scene and the drill path is kept
// (drill-tibial-tunnel.txt, replayable with `roboplan drill --replay`).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <vtkNew.h>

#include "rpBenchmarkChart.h"
#include "rpBlockMesher.h"
#include "rpDemoStages.h"
#include "rpDrillAnalytic.h"
#include "rpDrillBoneBuilder.h"
#include "rpDrillCommand.h"
#include "rpDrillProtection.h"
#include "rpGuidedDrill.h"
#include "rpDemoPlan.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpReport.h"
#include "rpServoLoadReport.h"
#include "rpSimulatedDevice.h"
#include "rpStageRunner.h"
#include "rpTunnelPicture.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

constexpr double BurrRadius = 2.0;  // a 4 mm burr: the pilot of an 8–10 mm reamed tunnel

// Bone (mm³ per material) inside the planned tunnel: each voxel's density as built times its
// coverage by the capsule (the same two-voxel ramp the burr carves).
std::vector<double> PlannedVolume(const DrillVolume& bone, const Vec3& a, const Vec3& b, double r) {
  std::vector<double> volume(bone.Materials().size(), 0.0);
  const Vec3 ab = b - a;
  const double ab2 = std::max(Norm2(ab), 1e-300), h = bone.Spacing();
  for (size_t s = 0; s < bone.AllocatedBlocks(); ++s) {
    const auto c = bone.BlockCoordinate(static_cast<int32_t>(s));
    const uint8_t* original = bone.BlockOriginal(static_cast<int32_t>(s));
    const uint8_t* codes = bone.BlockMaterials(static_cast<int32_t>(s));
    for (int v = 0; v < DrillVolume::BlockVoxels; ++v) {
      const int m = codes[v] & DrillVolume::MaterialMask;
      if (original[v] == 0 || m == 0) continue;
      const Vec3 p = bone.Grid().Center(c[0] * 8 + (v & 7), c[1] * 8 + ((v >> 3) & 7), c[2] * 8 + (v >> 6));
      const double t = std::clamp(Dot(p - a, ab) / ab2, 0.0, 1.0);
      const double coverage = 1.0 - DrillVolume::RampDensity(r - Norm(p - (a + ab * t)), h);
      volume[size_t(m - 1)] += original[v] / 255.0 * coverage * bone.VoxelVolume();
    }
  }
  return volume;
}

// The stroke that drills the planned tunnel: from a start clear of the bone on the plan's axis
// (the burr's whole sphere outside the tibia's model, 1 mm to spare) to the plan's target.
struct TunnelPlan {
  Vec3 From, To, Axis;
};

TunnelPlan StrokeOf(const TrajectorySnapshot& plan, const MeshSignedDistance& tibia) {
  const Vec3 axis = plan.Direction();
  double back = 0;
  while (back < 30 && tibia.SignedDistance(plan.Entry - axis * back) < BurrRadius + 1.0) back += 0.1;
  return {plan.Entry - axis * back, plan.Target, axis};
}

// The tibia's display model: the bone model the user sees (and the demo saves as tibia.vtp), in
// the segmentation's frame like the labels. False (and why) when the meshing stage made none.
bool TibiaModelSurface(const DemoState& state, const Segment& tibia, TriangleMesh& surface, std::string& why) {
  const auto id = state.DisplayModelIDOfSegment.find(tibia.ID);
  auto* model = id == state.DisplayModelIDOfSegment.end() ? nullptr
                                                          : vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id->second));
  if (model == nullptr) {
    why = "the tibia has no model";
    return false;
  }
  if (!PolyDataToTriangleMesh(model->GetPolyData(), nullptr, surface, why)) {
    why = "the tibia model: " + why;
    return false;
  }
  return true;
}

// How long the voxel tibia took, and that its surface is the tibia model's (within a fraction of
// a voxel) before the burr cuts it.
void ReportTunnelBone(DemoState& state, const std::string& stage, DrillVolume& bone, const DrillBoneReport& built,
                      const TriangleMesh& tibiaSurface) {
  state.Report->AddFigure(stage, "voxel tibia built", built.Seconds, "s",
                          "density from the " + built.Surface + " (" + std::to_string(built.SurfaceTriangles) + " triangles)");
  const SurfaceFit fit = MeasureSurfaceFit(bone, tibiaSurface);
  state.Report->AddFigureBelow(stage, "voxel tibia's surface from the tibia model, p95", fit.P95Mm, "mm", 0.15 * DemoDrillVoxelMm,
                               "mean " + std::to_string(fit.MeanMm).substr(0, 6) + " mm over " +
                                   std::to_string(fit.Vertices) + " vertices; target 0.15 voxel");
}

// Drills it in the Drilling logic: the simulated hand pushes the burr along the axis at 5 mm/s
// (through the soft tissue models: only the bone is touched); the drill path is kept.
DrillRunResult DrillAlongPlan(DemoState& state, const TunnelPlan& plan, vtkRPDrillingLogic* logic) {
  std::string error;
  auto path = std::make_shared<WaypointTrajectory>();
  path->Set({0.0, Norm(plan.To - plan.From) / 5.0}, {plan.From, plan.To}, error);
  logic->SetSimulatedTrajectory(path);
  logic->SetTouchOtherModels(false);
  DrillServoOptions servo;
  servo.RampSeconds = 0.05;
  logic->SetServoOptions(servo);
  logic->SetRecordPath((fs::path(state.Output) / "drill-tibial-tunnel.txt").string());
  DrillRunOptions run;
  const DrillControl on{true, BurrRadius, DrillControl{}.Rpm};
  const Vec3 to = plan.To;
  run.Schedule = [on](double) { return on; };
  run.Finished = [to](const DrillState& s) { return Norm(s.Proxy - to) < 0.05 || s.Stopped; };
  run.MaxSeconds = 60;
  run.Progress = [&state](double f, const std::string& m) { state.Runner->Progress(0.1 + 0.7 * f, m); };
  run.MeshEveryFrame = false;  // only the drilled tibia's last mesh is shown
  DrillRunResult result;
  if (!logic->RunSimulated(run, result, error)) throw std::runtime_error(error);
  return result;
}

// Removed against planned volume, the PCL's closest approach, the burr's path.
void ReportTunnelVolumes(DemoState& state, const std::string& stage, const TunnelPlan& plan,
                         const std::vector<Material>& materials, const std::vector<double>& planned,
                         const DrillRunResult& result, const DrillVolume& bone, const PlanSnapshot& snapshot,
                         double cutLead) {
  const DrillState& s = result.Final;
  const Vec3 &from = plan.From, &to = plan.To;
  double plannedTotal = 0;
  for (double v : planned) plannedTotal += v;
  const bool reached = Norm(s.Proxy - to) < 0.05;
  state.Report->AddFigure(stage, "drilled stroke (4 mm burr) length", Norm(to - from), "mm",
                          "the plan's axis from clear of the anteromedial cortex to its target, 1 mm into the joint");
  state.Report->AddFigure(stage, "bone inside the planned tunnel", plannedTotal, "mm³");
  if (reached) {
    state.Report->AddFigureBelow(stage, "removed volume against the planned tunnel's bone",
                                 100 * std::fabs(s.RemovedTotalMm3 - plannedTotal) / plannedTotal, "%", 5.0,
                                 std::to_string(static_cast<int>(s.RemovedTotalMm3 + 0.5)) + " mm³ removed");
  } else {
    state.Report->AddFigureBelow(stage, "burr reached the ACL footprint", 1.0, "", 0.5,
                                 s.Stopped ? "stopped by a protected structure" : "ran out of time");
  }
  for (size_t m = 0; m < materials.size(); ++m)
    state.Report->AddFigure(stage, "removed " + materials[m].Tissue, s.RemovedMm3[m], "mm³",
                            "planned " + std::to_string(static_cast<int>(planned[m] + 0.5)) + " mm³");
  std::vector<Vec3> burrPath;
  double deviation = 0;
  for (const DrillRecordLine& l : result.Records) {
    burrPath.push_back(l.Record.Proxy);
    if (l.Record.Flags & DrillRecordFlags::Cutting) {
      const double t = std::clamp(Dot(l.Record.Proxy - from, plan.Axis), 0.0, Norm(to - from));
      deviation = std::max(deviation, Norm(l.Record.Proxy - (from + plan.Axis * t)));
    }
  }
  // The burr's centre rides within a skin (0.02 voxel) of its last cut, and the cut leads it by
  // at most one cut's advance: the bound is r + h + skin + that lead.
  const double lead = cutLead;
  state.Report->AddFigureBelow(stage, "farthest removal from the burr's path", FarthestChangeFromPath(bone, burrPath), "mm",
                               BurrRadius + DemoDrillVoxelMm * (1 + BurrProxy::Skin) + lead + 1e-9,
                               "burr radius + one voxel + the cut's lead (" + std::to_string(static_cast<int>(lead * 1000 + 0.5)) + " µm)");
  state.Report->AddFigure(stage, "largest deviation of the cutting burr from the planned axis", deviation, "mm",
                          "the burr slides where the bone's surface is oblique to the push");
  // The burr's surface against each structure at risk of the plan, along the whole path.
  for (const StructureAtRiskSnapshot& structure : snapshot.StructuresAtRisk) {
    if (!structure.Signed) continue;
    double closest = HUGE_VAL;
    for (const Vec3& p : burrPath) closest = std::min(closest, structure.Signed->SignedDistance(p) - BurrRadius);
    state.Report->AddFigureAbove(stage, "closest approach of the burr to " + structure.Name, closest, "mm",
                                 structure.SafetyMarginMm,
                                 "its margin " + std::to_string(structure.SafetyMarginMm).substr(0, 3) + " mm" +
                                     (s.RefusedTicks ? "; the burr was refused there" : ""));
  }
}

// Force, servo timing and machine load, re-contour times.
void ReportTunnelTimings(DemoState& state, const std::string& stage, const DrillRunResult& result,
                         DrillVolume& bone, const DrillBoneReport& built, double maxForce) {
  const std::vector<double> contour = SplitDisplayFrames(result.Frames).ContourMs;
  double peak = 0;
  for (const DrillRecordLine& l : result.Records) peak = std::max(peak, Norm(l.Record.Force));
  state.Report->AddFigureBelow(stage, "peak force on the hand", peak, "N", maxForce + 1e-6,
                               "device maximum (eq. 6)");
  state.Report->AddFigureBelow(stage, "servo tick p99 while drilling (thread CPU)", result.TickCompute.P99Us, "µs", 100.0,
                               std::to_string(result.Ticks) + " ticks at 1 kHz, " + std::to_string(built.StoredBlocks) +
                                   " blocks of 8³ at 0.3 mm");
  // What the machine did to the servo's thread meanwhile, so a slow tick is seen as the machine's or ours.
  state.Report->AddFigure(stage, "servo thread preempted while drilling", double(result.Load.InvoluntarySwitches), "",
                          MachineLoadSummary(result.Load));
  BlockMesher whole(bone);
  const auto wholeStart = std::chrono::steady_clock::now();
  whole.ContourAll();
  const double wholeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wholeStart).count();
  state.Report->AddFigureBelow(stage, "dirty-block re-contour per 30 Hz frame, p95", NearestRankPercentile(contour, 0.95), "ms", 10.0,
                               "re-contouring this whole region takes " + std::to_string(static_cast<int>(wholeMs + 0.5)) +
                                   " ms");
}

// Force along the path: depth along the planned axis from the entry, per tissue being cut.
void WriteForceChart(DemoState& state, const std::string& stage, const TunnelPlan& plan,
                     const std::vector<Material>& materials, const DrillRunResult& result) {
  std::vector<bench::Series> series;
  std::vector<std::pair<std::vector<double>, std::vector<double>>> curves(materials.size() + 1);
  for (size_t i = 0; i < result.Records.size(); i += 5) {
    const DrillRecord& r = result.Records[i].Record;
    const size_t k = r.CutMaterial >= 0 && size_t(r.CutMaterial) < materials.size() ? size_t(r.CutMaterial) : materials.size();
    curves[k].first.push_back(Dot(r.Proxy - plan.From, plan.Axis));
    curves[k].second.push_back(Norm(r.Force));
  }
  for (size_t k = 0; k < curves.size(); ++k)
    if (!curves[k].first.empty())
      series.push_back({k < materials.size() ? "cutting " + materials[k].Tissue : "not cutting", curves[k].first, curves[k].second, true});
  bench::ChartOptions chart{"Force on the hand along the tibial tunnel (4 mm burr, 5 mm/s)",
                            "burr centre along the planned axis (mm from its start)", "force (N)"};
  std::string error;
  if (!series.empty())
    state.Report->AddPictureIf(
        bench::WriteChartPNG((fs::path(state.Output) / "drill-force-along-tunnel.png").string(), series, chart, error),
        stage, "drill-force-along-tunnel.png",
        "Force against depth: high through the cortex (hard, slow to cut: the hand pushes at the "
        "device's maximum), lower in the trabecular bone, zero where the burr breaks into the joint.",
        error);
}

void WriteTunnelPictureOf(DemoState& state, const std::string& stage, const TunnelPlan& plan,
                          const std::vector<Material>& materials, const DrillRunResult& result, const DrillVolume& bone,
                          vtkPolyData* mesh, const PlanSnapshot& snapshot) {
  TunnelPicture picture;
  picture.Bone = mesh;
  picture.Volume = &bone;
  picture.Materials = materials;
  picture.From = plan.From;
  picture.To = plan.To;
  picture.Radius = BurrRadius;
  for (size_t i = 0; i < result.Records.size(); i += 10) picture.Path.push_back(result.Records[i].Record.Proxy);
  TriangleMesh structures;
  for (const StructureAtRiskSnapshot& s : snapshot.StructuresAtRisk)
    if (s.Surface) structures.Append(*s.Surface, 0);
  if (!structures.Triangles.empty()) picture.Protected = TriangleMeshToPolyData(structures);
  picture.Title = "Tibial tunnel to the ACL footprint, structures at risk protected";
  std::string error;
  state.Report->AddPictureIf(WriteTunnelPicture((fs::path(state.Output) / "drill-tibial-tunnel.png").string(), picture, error),
                             stage, "drill-tibial-tunnel.png",
                             "The drilled tibia (left) and a section through the tunnel's axis (right): cortical bone "
                             "ivory, trabecular tan, drilled blue, the structures at risk (PCL, fibula, popliteal "
                             "vessels' stand-in) red, the planned tunnel green.",
                             error);
}

}  // namespace

std::shared_ptr<const PlanSnapshot> DemoPlan(const DemoState& state, std::string& why) {
  if (state.TunnelPlanID.empty()) {
    why = "the Plan stage made no tunnel";
    return nullptr;
  }
  return SnapshotPlan(state.Scene, why);
}

bool TibiaDrillSource(const DemoState& state, const Vec3& lo, const Vec3& hi, double voxelMm, DrillBoneSource& source,
                      std::string& why) {
  const auto* tibia = state.Segmentation ? state.Segmentation->GetSegmentByID("tibia") : nullptr;
  if (tibia == nullptr) {
    why = "the tibia was not segmented in this run";
    return false;
  }
  if (!TibiaModelSurface(state, *tibia, source.BoneSurface, why)) return false;
  source.Labels = FromNode(state.Segmentation);
  source.BoneLabels = {tibia->LabelValue};
  source.BoneTissues = {tibia->TissueClass};
  if (state.CT) source.CT = FromNode(state.CT);
  source.Spacing = voxelMm;
  source.HasRegion = true;
  source.RegionLo = lo;
  source.RegionHi = hi;
  return true;
}

void DrillTibialTunnel(DemoState& state) {
  const std::string stage = "Tibial tunnel (drilling)";
  std::string why;
  const std::shared_ptr<const PlanSnapshot> snapshot = DemoPlan(state, why);
  const TrajectorySnapshot* planned = snapshot ? ChooseTrajectory(*snapshot, state.TunnelPlanID, why) : nullptr;
  DrillBoneSource source;
  MeshSignedDistance tibiaDistance;
  if (!planned || !TibiaDrillSource(state, planned->Entry, planned->Target, DemoDrillVoxelMm, source, why) ||
      !tibiaDistance.Build(source.BoneSurface, why)) {
    state.Report->AddNotScored(stage, "tibial tunnel", why);
    return;
  }
  const TunnelPlan plan = StrokeOf(*planned, tibiaDistance);
  const Vec3 margin{15, 15, 15};
  source.RegionLo = Min(plan.From, plan.To) - margin;
  source.RegionHi = Max(plan.From, plan.To) + margin;
  state.Runner->Progress(0.05, "voxel tibia");

  // The voxel tibia and the drilled tibia's model node ("Tibia (drilled)") in the Drilling logic;
  // the plan's structures at risk protected in it.
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(state.Scene);
  std::string error;
  if (!logic->BuildBone(source, {"Tibia"}, error)) throw std::runtime_error(error);
  DrillVolume& bone = *logic->GetBone();
  ProtectRegions(bone, ProtectedRegionsOf(*snapshot));
  const std::vector<Material>& materials = logic->GetMaterials();
  ReportTunnelBone(state, stage, bone, logic->GetBoneReport(), source.BoneSurface);
  const std::vector<double> plannedVolume = PlannedVolume(bone, plan.From, plan.To, BurrRadius);

  const DrillRunResult result = DrillAlongPlan(state, plan, logic);
  ReportTunnelVolumes(state, stage, plan, materials, plannedVolume, result, bone, *snapshot,
                      logic->GetSession()->Servo().MaxCutLead(DrillControl{}.Rpm, 0.001));
  ReportTunnelTimings(state, stage, result, bone, logic->GetBoneReport(), SimulatedDevice::DefaultInfo().MaxForce);
  vtkPolyData* mesh = logic->GetDrilledMesh();
  state.Runner->Progress(0.9, "pictures");

  if (!CanDrawPicturesOrWarn(state, stage, "tibial tunnel pictures")) return;
  WriteForceChart(state, stage, plan, materials, result);
  WriteTunnelPictureOf(state, stage, plan, materials, result, bone, mesh, *snapshot);
}

}  // namespace rp
