#include "rpGuidedDrill.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <vtkNew.h>

#include "rpDataLoader.h"
#include "rpExecutionScoreJson.h"
#include "rpFixtureConstraint.h"
#include "rpGuidedDrillJson.h"
#include "rpSimulatedDevice.h"
#include "vtkRPPlanningLogic.h"

namespace rp {

namespace {
// The stylus's shaft (+z) points back from the tip against the plan: the burr leads along −z.
Pose AlongPlan(const TrajectoryAxis& plan) {
  const Vec3 z = -plan.Direction();
  Vec3 x = Vec3{1, 0, 0} - z * z.x;
  if (Norm(x) < 0.1) x = Vec3{0, 1, 0} - z * z.y;
  x = Normalized(x);
  const Vec3 y = Cross(z, x);
  Pose pose;
  const double r[9] = {x.x, y.x, z.x, x.y, y.y, z.y, x.z, y.z, z.z};
  for (int i = 0; i < 9; ++i) pose.R[i] = r[i];
  return pose;
}

void ScoreRun(const GuidedDrillOptions& o, vtkRPDrillingLogic* logic, GuidedDrillResult& result, std::string& error,
              bool& ok) {
  ExecutionInput input;
  input.Plan = o.Plan;
  input.PlanDiameterMm = o.PlanDiameterMm;
  input.ToolRadiusMm = o.BurrRadiusMm;
  input.Path = result.Path;
  input.Bone = logic->GetBoneReport().BoneSurface.get();
  input.Structures = o.Structures;
  logic->GetBone()->ForEachRemoved([&](const Vec3& c, double v) { input.Removed.push_back({c, v}); });
  ok = ScoreExecution(input, result.Score, error);
  if (!ok) return;
  for (const StructureClearance& c : result.Score.Clearance)
    result.EnteredForbidden = result.EnteredForbidden || c.ClosestMm < c.MarginMm - 1e-6;
  result.DepthOvershootMm = std::max(0.0, result.Score.DepthErrorMm);
}
}  // namespace

std::shared_ptr<const PlanSnapshot> SnapshotPlan(vtkRPScene* scene, std::string& error) {
  vtkNew<vtkRPPlanningLogic> planning;
  planning->SetScene(scene);
  return planning->MakePlanSnapshot(error);
}

std::shared_ptr<const PlanSnapshot> LoadPlan(vtkRPScene* scene, const std::string& file, std::string& error) {
  const LoadResult loaded = LoadPath(scene, file);
  if (!loaded.Ok) {
    error = loaded.Error;
    return nullptr;
  }
  auto plan = SnapshotPlan(scene, error);
  if (plan && plan->Trajectories.empty()) {
    error = "'" + file + "' holds no complete trajectory (a Slicer markups line: entry and target)";
    return nullptr;
  }
  return plan;
}

const TrajectorySnapshot* ChooseTrajectory(const PlanSnapshot& plan, const std::string& name, std::string& error) {
  const TrajectorySnapshot* t = name.empty() ? (plan.Trajectories.empty() ? nullptr : &plan.Trajectories.front())
                                             : plan.FindTrajectory(name);
  if (t) return t;
  error = "the plan has no trajectory '" + name + "' (it has:";
  for (const TrajectorySnapshot& each : plan.Trajectories) error += " '" + each.Name + "'";
  error += ")";
  return nullptr;
}

std::vector<ScoredStructure> ScoredStructuresOf(const PlanSnapshot& plan) {
  std::vector<ScoredStructure> out;
  for (const StructureAtRiskSnapshot& s : plan.StructuresAtRisk)
    if (s.Signed) out.push_back({s.Name, s.Signed.get(), s.SafetyMarginMm});
  return out;
}

std::vector<ProtectedRegion> ProtectedRegionsOf(const PlanSnapshot& plan) {
  std::vector<ProtectedRegion> out;
  for (const StructureAtRiskSnapshot& s : plan.StructuresAtRisk)
    if (s.Signed) out.push_back({s.Name, s.Signed, s.SafetyMarginMm});
  return out;
}

bool DrillPlannedTrajectory(vtkRPDrillingLogic* logic, const PlanSnapshot& plan, const TrajectorySnapshot& trajectory,
                            PlanFixtureChoice choice, GuidedDrillOptions options, GuidedDrillResult& result,
                            std::string& error) {
  if (!logic || !logic->HasBone()) {
    error = "drilling the plan: build the bone first";
    return false;
  }
  if (!TrajectoryAxis::Make(trajectory.Entry, trajectory.Target, options.Plan, error)) return false;
  ProtectRegions(*logic->GetBone(), ProtectedRegionsOf(plan));
  choice.Trajectory = trajectory.NodeID.empty() ? trajectory.Name : trajectory.NodeID;
  const std::shared_ptr<const FixtureSet> fixtures = BuildPlanFixtures(plan, choice, error);
  if (!fixtures) return false;
  options.PlanDiameterMm = trajectory.ToolDiameterMm;
  options.Fixtures = fixtures->Count() > 0 ? fixtures : nullptr;
  options.Structures = ScoredStructuresOf(plan);
  return RunGuidedDrill(logic, options, result, error);
}

const std::vector<ExecutionWay>& ExecutionWays() {
  static const std::vector<ExecutionWay> ways = {{"free hand", "none"},
                                                 {"axis guidance and depth stop", "axis,depth"},
                                                 {"guidance and forbidden regions", "axis,depth,forbidden"}};
  return ways;
}

nlohmann::json GuidedDrillJson(const GuidedDrillResult& result) {
  nlohmann::json doc = ExecutionScoreJson(result.Score);
  doc["enteredForbidden"] = result.EnteredForbidden;
  doc["drillSeconds"] = result.DrillSeconds;
  doc["depthOvershootMm"] = result.DepthOvershootMm;
  return doc;
}

namespace {
// The run's end (GuidedDrillOptions): the intent over, and the burr at its end or making no progress.
std::function<bool(const DrillState&)> ArrivedOrStalled(const GuidedDrillOptions& o, double intentSeconds, double endDepth) {
  double progressDepth = -std::numeric_limits<double>::infinity(), progressTime = 0;
  return [=](const DrillState& s) mutable {
    const double depth = o.Plan.Depth(s.Proxy);
    if (depth > progressDepth + o.StallProgressMm) {
      progressDepth = depth;
      progressTime = s.Time;
    }
    if (s.Time < intentSeconds) return false;
    return depth >= endDepth - o.ArrivalToleranceMm || s.Time - progressTime >= o.StallSeconds;
  };
}
}  // namespace

bool RunGuidedDrill(vtkRPDrillingLogic* logic, const GuidedDrillOptions& o, GuidedDrillResult& result, std::string& error) {
  result = GuidedDrillResult{};
  if (!logic || !logic->HasBone()) {
    error = "guided drilling: build the bone first";
    return false;
  }
  if (!(o.SpeedMmPerS > 0) || !(o.BurrRadiusMm > 0)) {
    error = "guided drilling: the hand's speed and the burr's radius must be positive";
    return false;
  }
  // The hand's intent: from the entry along the plan to PushBeyondMm past the target.
  auto intent = std::make_shared<WaypointTrajectory>();
  const Vec3 start = o.Plan.Entry() + o.IntentOffsetMm;
  const Vec3 end = o.Plan.PointAt(o.Plan.Length() + o.PushBeyondMm) + o.IntentOffsetMm;
  const double duration = (o.Plan.Length() + o.PushBeyondMm) / o.SpeedMmPerS;
  if (!intent->Set({0.0, duration}, {start, end}, error)) return false;
  intent->SetOrientation(AlongPlan(o.Plan));
  logic->SetSimulatedTrajectory(intent);
  if (o.Hand) logic->SetSimulatedHand(o.Noise, o.Grip);
  else logic->ClearSimulatedHand();
  if (o.Fixtures) {
    const std::shared_ptr<const FixtureSet> fixtures = o.Fixtures;
    logic->SetConstraints([fixtures] { return MakeFixtureConstraints(fixtures); });
  } else {
    logic->SetConstraints(nullptr);
  }
  DrillServoOptions servo = logic->GetServoOptions();
  servo.FeedRate = o.FeedRate;
  servo.RampSeconds = 0;  // the burr starts in the bone: no ramp to hide a jump
  logic->SetServoOptions(servo);
  logic->SetLoopOptions(o.Loop);
  logic->SetRecordPath(o.RecordPath);
  const DrillControl on{true, o.BurrRadiusMm, o.Rpm};
  logic->PlaceBurr(start, on);
  DrillRunOptions run;
  run.Realtime = o.Realtime;
  run.Schedule = [on](double) { return on; };
  run.Finished = ArrivedOrStalled(o, duration, Dot(end - o.Plan.Entry(), o.Plan.Direction()));
  run.SettleSeconds = o.SettleSeconds;
  run.MaxSeconds = std::max(o.MaxSeconds, duration + o.SettleSeconds);
  run.MeshEveryFrame = o.Realtime;
  if (o.Progress) {
    const double scale = run.MaxSeconds / (duration + o.SettleSeconds);  // the run's fraction of MaxSeconds
    run.Progress = [&o, scale](double fraction, const std::string& message) { o.Progress(std::min(1.0, fraction * scale), message); };
  }
  if (!logic->RunSimulated(run, result.Run, error)) return false;
  for (const DrillRecordLine& l : result.Run.Records) {
    if (!(l.Record.Flags & DrillRecordFlags::BurrOn)) continue;
    result.Path.push_back(l.Record.Proxy);
    if (l.Record.Flags & DrillRecordFlags::Cutting) result.DrillSeconds = l.Record.Time;
  }
  result.Fixtures = o.Fixtures;
  bool ok = false;
  ScoreRun(o, logic, result, error, ok);
  return ok;
}

}  // namespace rp
