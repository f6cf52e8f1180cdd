// Demo stage (issue 38): the plan executed three ways under one hand. The tibial tunnel and the
// screw's pilot hole are each drilled by the simulated hand (0.2 mm RMS tremor at 8–12 Hz, 1 mm/s
// drift, the same seed) free hand, with axis guidance and a depth stop, and with guidance and the
// structures at risk as forbidden regions (rpGuidedDrill.h: ExecutionWays, DrillPlannedTrajectory,
// the one path `roboplan drill --plan` and the guidance benchmark take), each on a freshly built
// voxel tibia, and scored against the plan (rpExecutionScore). The report states each score
// beside the targets (guided: entry and tip within 0.5 mm, angle within 1°, depth
// overshoot ≤ 0.1 mm; no forbidden region entered), the free hand beside as the baseline, and
// charts the tunnel's accuracy against the guidance's stiffness and against the drilling time
// (the hand's speed). report.json lists them under "executions" and "executionSweeps".
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpBenchmarkChart.h"
#include "rpDemoPlan.h"
#include "rpDemoStages.h"
#include "rpGuidedDrill.h"
#include "rpGuidedDrillJson.h"
#include "rpPlanFixtures.h"
#include "rpReport.h"
#include "rpStageRunner.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

const std::string ExecutionsStage = "Executions (three ways)";
// The hand of issue 38's targets (the guidance benchmark's): its tremor, drift, seed and speed.
constexpr double TremorMm = 0.2, DriftMmPerS = 1.0, HandSpeed = 2.5, FeedRate = 8;
constexpr uint64_t Seed = 3;

struct Execution {
  std::string Plan, Way, Fixtures;
  double AxisStiffness = 0, Speed = HandSpeed;
  double BoneSeconds = 0, Seconds = 0;  // the voxel tibia's build and the whole execution (wall)
  GuidedDrillResult Result;
};

// One execution on a fresh voxel tibia around the trajectory (in a scene of its own: the demo's
// scene keeps the drilling stage's drilled tibia only).
Execution Execute(DemoState& state, const PlanSnapshot& plan, const TrajectorySnapshot& trajectory, const ExecutionWay& way,
                  double axisStiffness, double speed) {
  const auto start = std::chrono::steady_clock::now();
  Execution e{trajectory.Name, way.Name, way.Fixtures, axisStiffness, speed, 0, 0, {}};
  const double pad = 0.5 * trajectory.ToolDiameterMm + 6;  // the hand's drift and the push past the target
  const Vec3 margin{pad, pad, pad};
  DrillBoneSource source;
  std::string error;
  if (!TibiaDrillSource(state, Min(trajectory.Entry, trajectory.Target) - margin, Max(trajectory.Entry, trajectory.Target) + margin,
                        DemoDrillVoxelMm, source, error))
    throw std::runtime_error(error);
  vtkNew<vtkRPScene> scratch;
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(scratch);
  logic->SetTouchOtherModels(false);
  PlanFixtureChoice choice;
  if (axisStiffness > 0) choice.AxisTuning.Stiffness = axisStiffness;
  GuidedDrillOptions o;
  o.BurrRadiusMm = 0.5 * trajectory.ToolDiameterMm;
  o.SpeedMmPerS = speed;
  o.FeedRate = FeedRate;
  o.Noise.TremorMm = TremorMm;
  o.Noise.DriftMmPerS = DriftMmPerS;
  o.Noise.Seed = Seed;
  if (!logic->BuildBone(source, {"Tibia"}, error) || !ParseFixtureKinds(way.Fixtures, choice, error) ||
      !DrillPlannedTrajectory(logic, plan, trajectory, choice, o, e.Result, error))
    throw std::runtime_error(trajectory.Name + ", " + way.Name + ": " + error);
  e.AxisStiffness = e.Result.Fixtures && way.Fixtures.find("axis") != std::string::npos ? choice.AxisTuning.Stiffness : 0;
  e.BoneSeconds = logic->GetBoneReport().Seconds;
  e.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return e;
}

nlohmann::json Json(const Execution& e) {
  nlohmann::json doc = GuidedDrillJson(e.Result);
  doc["name"] = e.Plan + ": " + e.Way;
  doc["plan"] = e.Plan;
  doc["way"] = e.Way;
  doc["fixtures"] = e.Fixtures;
  doc["axisStiffnessNPerMm"] = e.AxisStiffness;
  doc["handSpeedMmPerS"] = e.Speed;
  doc["hand"] = {{"tremorMm", TremorMm}, {"driftMmPerS", DriftMmPerS}, {"seed", Seed}};
  doc["wallSeconds"] = e.Seconds;
  doc["boneBuildSeconds"] = e.BoneSeconds;
  return doc;
}

// Each score beside the targets; the free hand is the baseline, shown unscored.
void ReportExecution(DemoState& state, const Execution& e) {
  const ExecutionScore& s = e.Result.Score;
  const std::string name = e.Plan + ", " + e.Way + ": ";
  const bool guided = e.Fixtures.find("axis") != std::string::npos;
  const bool forbidden = e.Fixtures.find("forbidden") != std::string::npos;
  auto scored = [&](const std::string& what, double value, const std::string& unit, double maximum) {
    if (guided) state.Report->AddFigureBelow(ExecutionsStage, name + what, value, unit, maximum);
    else state.Report->AddFigure(ExecutionsStage, name + what, value, unit, "free hand: the baseline");
  };
  scored("entry offset", s.EntryOffsetMm, "mm", 0.5);
  scored("tip offset", s.TipOffsetMm, "mm", 0.5);
  scored("angle to the plan", s.AngleDeg, "°", 1.0);
  if (guided) state.Report->AddFigureBelow(ExecutionsStage, name + "depth overshoot", e.Result.DepthOvershootMm, "mm", 0.1,
                                           "depth error " + std::to_string(s.DepthErrorMm).substr(0, 6) + " mm");
  else state.Report->AddFigure(ExecutionsStage, name + "depth error", s.DepthErrorMm, "mm", "free hand: no depth stop");
  state.Report->AddFigure(ExecutionsStage, name + "largest deviation from the planned axis", s.MaxDeviationMm, "mm");
  const double entered = e.Result.EnteredForbidden ? 1.0 : 0.0;
  if (forbidden) state.Report->AddFigureBelow(ExecutionsStage, name + "entered a forbidden region", entered, "", 0.5, "1: yes, 0: no");
  else state.Report->AddFigure(ExecutionsStage, name + "came within a structure's margin", entered, "", "1: yes, 0: no");
  state.Report->AddFigure(ExecutionsStage, name + "drilling time", e.Result.DrillSeconds, "s",
                          std::to_string(e.Result.Run.Ticks) + " servo ticks at 1 kHz (scripted)");
}

void Chart(DemoState& state, const std::string& file, const std::string& title, const std::string& x,
           const std::vector<bench::Series>& series, const std::string& caption) {
  bench::ChartOptions options{title, x, "offset (mm) / angle (°)"};
  std::string error;
  state.Report->AddPictureIf(bench::WriteChartPNG((fs::path(state.Output) / file).string(), series, options, error), ExecutionsStage,
                             file, caption, error);
}

// The tunnel's accuracy against the axis guidance's stiffness and against the drilling time.
nlohmann::json Sweeps(DemoState& state, const PlanSnapshot& plan, const TrajectorySnapshot& tunnel, const Execution& guided,
                      const Execution& free) {
  const ExecutionWay way = ExecutionWays()[1];
  std::vector<Execution> byStiffness, bySpeed;
  const double defaultStiffness = DefaultFixtureTuning(FixtureKind::AxisGuidance).Stiffness;
  for (double k : {0.15, 0.3}) {
    state.Runner->Progress(0.7 + 0.05 * double(byStiffness.size()), "tunnel, stiffness " + std::to_string(k).substr(0, 4) + " N/mm");
    byStiffness.push_back(Execute(state, plan, tunnel, way, k, HandSpeed));
  }
  byStiffness.push_back(guided);  // the default stiffness: the guided execution itself
  bySpeed.push_back(guided);
  for (double v : {5.0, 10.0}) {
    state.Runner->Progress(0.8 + 0.05 * double(bySpeed.size()), "tunnel at " + std::to_string(v).substr(0, 4) + " mm/s");
    bySpeed.push_back(Execute(state, plan, tunnel, way, defaultStiffness, v));
  }
  nlohmann::json doc = {{"stiffness", nlohmann::json::array()}, {"speed", nlohmann::json::array()}};
  bench::Series kEntry{"entry", {}, {}}, kTip{"tip", {}, {}}, kAngle{"angle (°)", {}, {}};
  for (const Execution& e : byStiffness) {
    doc["stiffness"].push_back(Json(e));
    for (auto* s : {&kEntry, &kTip, &kAngle}) s->X.push_back(e.AxisStiffness);
    kEntry.Y.push_back(e.Result.Score.EntryOffsetMm), kTip.Y.push_back(e.Result.Score.TipOffsetMm);
    kAngle.Y.push_back(e.Result.Score.AngleDeg);
  }
  bench::Series tEntry{"entry", {}, {}}, tTip{"tip", {}, {}}, tAngle{"angle (°)", {}, {}};
  for (const Execution& e : bySpeed) {
    doc["speed"].push_back(Json(e));
    for (auto* s : {&tEntry, &tTip, &tAngle}) s->X.push_back(e.Result.DrillSeconds);
    tEntry.Y.push_back(e.Result.Score.EntryOffsetMm), tTip.Y.push_back(e.Result.Score.TipOffsetMm);
    tAngle.Y.push_back(e.Result.Score.AngleDeg);
  }
  if (!CanDrawPicturesOrWarn(state, ExecutionsStage, "execution charts")) return doc;
  char baseline[160];
  std::snprintf(baseline, sizeof baseline, " The free hand under the same hand: entry %.2f mm, tip %.2f mm, angle %.2f°.",
                free.Result.Score.EntryOffsetMm, free.Result.Score.TipOffsetMm, free.Result.Score.AngleDeg);
  Chart(state, "executions-accuracy-vs-stiffness.png",
        "Tibial tunnel with axis guidance and depth stop: accuracy against the guidance's stiffness", "axis guidance stiffness (N/mm)",
        {kEntry, kTip, kAngle},
        "The tunnel drilled with axis guidance and a depth stop (0.2 mm tremor, 1 mm/s drift, 2.5 mm/s) at three "
        "stiffnesses of the guidance: entry and tip offsets and the angle to the plan (targets 0.5 mm, 1°)." + std::string(baseline));
  Chart(state, "executions-accuracy-vs-time.png",
        "Tibial tunnel with axis guidance and depth stop: accuracy against drilling time", "drilling time (s)",
        {tEntry, tTip, tAngle},
        "The same guided tunnel drilled at 2.5, 5 and 10 mm/s by the same hand: accuracy against the time it took "
        "(speed against accuracy)." + std::string(baseline));
  return doc;
}

}  // namespace

void ExecutePlans(DemoState& state) {
  std::string why;
  const std::shared_ptr<const PlanSnapshot> plan = DemoPlan(state, why);
  if (!plan) {
    state.Report->AddNotScored(ExecutionsStage, "the plan's executions", why);
    return;
  }
  std::vector<const TrajectorySnapshot*> trajectories;
  for (const std::string& id : {state.TunnelPlanID, state.ScrewPlanID}) {
    const TrajectorySnapshot* t = id.empty() ? nullptr : ChooseTrajectory(*plan, id, why);
    if (!t) throw std::runtime_error(why);
    trajectories.push_back(t);
  }
  std::vector<Execution> executions;
  for (const TrajectorySnapshot* t : trajectories)
    for (const ExecutionWay& way : ExecutionWays()) {
      state.Runner->Progress(0.1 * double(executions.size()), t->Name + ", " + way.Name);
      executions.push_back(Execute(state, *plan, *t, way, 0, HandSpeed));
      ReportExecution(state, executions.back());
    }
  nlohmann::json doc = nlohmann::json::array();
  for (const Execution& e : executions) doc.push_back(Json(e));
  state.Report->SetJsonSection("executions", doc.dump());
  // executions[0..2]: the tunnel free hand, guided, guided with forbidden regions.
  state.Report->SetJsonSection("executionSweeps", Sweeps(state, *plan, *trajectories[0], executions[1], executions[0]).dump());
}

}  // namespace rp
