// Guidance benchmarks (issue 38): the servo tick with all four virtual fixtures, and what they buy.
//  * Haptics: the renderer's tick (a bone of 20 480 triangles touched, a vessel of 5 120) with the
//    four fixtures (surface constraint on the bone, axis guidance, depth stop, forbidden region
//    around the vessel) against the same tick without them; thread-CPU time per tick p50/p99/max
//    over a scripted hand that presses on the walls and slides along them. Beside it, the VTK way
//    to get the same distances each tick (vtkImplicitPolyDataDistance's closest point on the bone
//    and the vessel), in the same run.
//  * Drilling: the drill servo's tick at 0.2 mm voxels with the four fixtures (axis, depth stop, a
//    forbidden region beside the tunnel, a surface constraint on a plane through the plan) and
//    without, through the one drill path (vtkRPDrillingLogic::RunSimulated, scripted ticks).
//  * Accuracy: the same planned tunnel drilled by the simulated hand (0.2 mm tremor, 1 mm/s drift)
//    free and with axis guidance + depth stop, over seeds: entry, tip, angle; against the guidance's
//    stiffness and against the hand's speed (the drilling time); depth overshoot with the stop at
//    2–10 mm/s.
//  * The three executions of one plan under one hand (free; axis guidance + depth stop; guidance
//    + a forbidden region around a vessel beside the tunnel), scored: "executions".
// Targets: tick p99 < 100 µs in both servos; guided entry and tip within 0.5 mm and angle within
// 1°; depth overshoot ≤ 0.1 mm. Figures go to $ROBOPLAN_BENCHMARK_OUTPUT (./benchmark-output):
// guidance_benchmark.json (everything), guidance_ticks.csv/.png (tick with and without the
// fixtures; drilling 0/1, fixtures 0/4), guidance_accuracy.csv (seed, guided 0/1, the scores) and
// the accuracy charts. A quick run (ROBOPLAN_BENCHMARK_QUICK) drills at 0.3 mm, one seed, two
// stiffnesses and two speeds.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>
#include <vtkImplicitPolyDataDistance.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpAxisGuidance.h"
#include "rpBenchmarkChart.h"
#include "rpBenchmarkConditions.h"
#include "rpBenchmarkMain.h"
#include "rpDepthStop.h"
#include "rpDeviceProfiles.h"
#include "rpFixtureConstraint.h"
#include "rpForbiddenRegion.h"
#include "rpGuidedDrill.h"
#include "rpGuidedDrillJson.h"
#include "rpHapticRenderer.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSurfaceConstraint.h"
#include "rpTimingHistogram.h"
#include "vtkRPScene.h"

using rp::Vec3;

namespace {

int64_t ThreadNs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

rp::TrajectoryAxis Axis(const Vec3& a, const Vec3& b) {
  rp::TrajectoryAxis axis;
  std::string error;
  rp::TrajectoryAxis::Make(a, b, axis, error);
  return axis;
}

struct TickFigures {
  double P50 = 0, P99 = 0, Max = 0;
  uint64_t Ticks = 0;
};

TickFigures FiguresOf(const rp::TimingStats& s, uint64_t ticks) { return {s.P50Us, s.P99Us, s.MaxUs, ticks}; }

nlohmann::json Json(const TickFigures& f) {
  return {{"tickP50Us", f.P50}, {"tickP99Us", f.P99}, {"tickMaxUs", f.Max}, {"ticks", f.Ticks}};
}

// ---- the haptic tick
struct HapticWorld {
  rp::TriangleMesh Bone = rp::shapes::Sphere({0, 0, -30}, 25, 5);   // 20 480 triangles
  rp::TriangleMesh Vessel = rp::shapes::Sphere({9, 0, -38}, 3, 4);  // 5 120
  rp::TrajectoryAxis Plan = Axis({0, 0, 0}, {0, 0, -40});
  std::unique_ptr<rp::HapticScene> Scene;
  std::shared_ptr<const rp::FixtureSet> Fixtures;

  HapticWorld() {
    rp::MaterialTable table;
    table.Add({"bone", 0.7, 0.001, 0.3, 0.2});
    std::vector<std::string> warnings;
    std::string error;
    this->Scene = rp::HapticScene::Build({{"bone", "bone", this->Bone}}, table, warnings, error);
    auto set = std::make_shared<rp::FixtureSet>();
    set->Add(rp::SurfaceConstraint::Mesh(1, "bone", this->Bone, error), rp::DefaultFixtureTuning(rp::FixtureKind::SurfaceConstraint),
             true, error);
    set->Add(std::make_shared<rp::AxisGuidance>(2, "plan", this->Plan), rp::DefaultFixtureTuning(rp::FixtureKind::AxisGuidance),
             true, error);
    set->Add(std::make_shared<rp::DepthStop>(3, "plan", this->Plan), rp::DefaultFixtureTuning(rp::FixtureKind::DepthStop), true,
             error);
    set->Add(rp::ForbiddenRegion::Make(4, "vessel", this->Vessel, 1.0, error),
             rp::DefaultFixtureTuning(rp::FixtureKind::ForbiddenRegion), true, error);
    this->Fixtures = set;
  }
};

// The hand: down the axis into the bone and past the stop, a sideways wander towards the vessel,
// a 10 Hz tremor; 8 000 ticks.
rp::Pose HandAt(int i) {
  const double t = i * 0.001;
  rp::Pose p;
  p.T = {2.5 * std::sin(0.9 * t) + 0.2 * std::sin(62.8 * t), 0.2 * std::cos(71 * t), 8 - 7.0 * t};
  return p;
}

TickFigures HapticTicks(const HapticWorld& world, bool fixtures, int ticks) {
  rp::HapticRenderer renderer;
  rp::DeviceProfile omni;
  std::string error;
  rp::FindDeviceProfile("omni", omni, error);
  renderer.SetDevice(omni.Info);
  renderer.SetScene(world.Scene.get());
  auto constraints = fixtures ? rp::MakeFixtureConstraints(world.Fixtures) : nullptr;
  renderer.Reset(HandAt(0));
  rp::TimingHistogram compute(100, 20000);
  for (int i = 1; i <= ticks; ++i) {
    const rp::Pose pose = HandAt(i);
    const int64_t start = ThreadNs();
    renderer.Update(pose, 0.001, constraints.get());
    compute.Record(ThreadNs() - start);
  }
  return FiguresOf(compute.Stats(), ticks);
}

// The VTK way to the two distances the mesh fixtures need each tick (the surface constraint's
// closest point on the bone, the forbidden region's signed distance to the vessel).
TickFigures VtkDistanceTicks(const HapticWorld& world, int ticks) {
  vtkNew<vtkImplicitPolyDataDistance> bone, vessel;
  bone->SetInput(rp::TriangleMeshToPolyData(world.Bone));
  vessel->SetInput(rp::TriangleMeshToPolyData(world.Vessel));
  rp::TimingHistogram compute(100, 200000);
  double sink = 0;
  for (int i = 1; i <= ticks; ++i) {
    const Vec3 p = HandAt(i).T;
    double x[3] = {p.x, p.y, p.z}, closest[3];
    const int64_t start = ThreadNs();
    sink += bone->EvaluateFunctionAndGetClosestPoint(x, closest) + vessel->EvaluateFunction(x);
    compute.Record(ThreadNs() - start);
  }
  benchmark::DoNotOptimize(sink);
  return FiguresOf(compute.Stats(), ticks);
}

// ---- the drilling tick and the accuracy runs, on an analytic block (30 × 30 × 40 mm)
const rp::TrajectoryAxis DrillPlan = Axis({0, 0, 0}, {0, 0, -25});

std::shared_ptr<const rp::FixtureSet> DrillFixtures(bool axis, bool depth, bool forbidden, bool surface, double k,
                                                    std::shared_ptr<const rp::MeshSignedDistance> vessel) {
  auto set = std::make_shared<rp::FixtureSet>();
  std::string error;
  rp::FixtureTuning axisTuning = rp::DefaultFixtureTuning(rp::FixtureKind::AxisGuidance);
  if (k > 0) axisTuning.Stiffness = k;
  if (axis) set->Add(std::make_shared<rp::AxisGuidance>(1, "plan", DrillPlan), axisTuning, true, error);
  if (depth)
    set->Add(std::make_shared<rp::DepthStop>(2, "plan", DrillPlan), rp::DefaultFixtureTuning(rp::FixtureKind::DepthStop), true,
             error);
  if (forbidden && vessel)
    set->Add(rp::ForbiddenRegion::Make(3, "vessel", vessel, 1.0, error),
             rp::DefaultFixtureTuning(rp::FixtureKind::ForbiddenRegion), true, error);
  if (surface)
    set->Add(rp::SurfaceConstraint::Plane(4, "cut", {0, 0, 0}, {0, 1, 0}), rp::DefaultFixtureTuning(rp::FixtureKind::SurfaceConstraint),
             true, error);
  return set;
}

struct Execution {
  double Entry = 0, Tip = 0, Angle = 0, Depth = 0, Seconds = 0, Outside = 0;
  TickFigures Tick;
  bool Forbidden = false;
};

Execution Drill(double voxel, std::shared_ptr<const rp::FixtureSet> fixtures, double speed, uint64_t seed,
                double tremor = 0.2, double drift = 1.0, std::shared_ptr<const rp::MeshSignedDistance> vessel = nullptr) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPDrillingLogic> logic;
  logic->SetScene(scene);
  logic->SetTouchOtherModels(false);
  std::string error;
  Execution e;
  if (!logic->BuildBlockBone({-15, -15, -40}, {15, 15, 0}, 0, voxel, error)) {
    std::cerr << error << "\n";
    return e;
  }
  rp::GuidedDrillOptions o;
  o.Plan = DrillPlan;
  o.PlanDiameterMm = 4;
  o.BurrRadiusMm = 2;
  o.SpeedMmPerS = speed;
  o.FeedRate = 8;
  o.Noise.TremorMm = tremor;
  o.Noise.DriftMmPerS = drift;
  o.Noise.Seed = seed;
  o.Fixtures = std::move(fixtures);
  if (vessel) o.Structures = {{"vessel", vessel.get(), 1.0}};
  rp::GuidedDrillResult r;
  if (!rp::RunGuidedDrill(logic, o, r, error)) {
    std::cerr << error << "\n";
    return e;
  }
  e.Entry = r.Score.EntryOffsetMm;
  e.Tip = r.Score.TipOffsetMm;
  e.Angle = r.Score.AngleDeg;
  e.Depth = r.Score.DepthErrorMm;
  e.Seconds = r.DrillSeconds;
  e.Outside = r.Score.OutsideVolumeMm3;
  e.Forbidden = r.EnteredForbidden;
  e.Tick = FiguresOf(r.Run.TickCompute, r.Run.Ticks);
  return e;
}

nlohmann::json Json(const Execution& e) {
  return {{"entryOffsetMm", e.Entry}, {"tipOffsetMm", e.Tip},     {"angleDeg", e.Angle},
          {"depthErrorMm", e.Depth},  {"drillSeconds", e.Seconds}, {"outsideVolumeMm3", e.Outside},
          {"enteredForbidden", e.Forbidden}, {"servo", Json(e.Tick)}};
}

void Chart(const std::string& file, const std::string& title, const std::string& x, const std::string& y,
           const std::vector<rp::bench::Series>& series) {
  rp::bench::ChartOptions options;
  options.Title = title;
  options.XLabel = x;
  options.YLabel = y;
  std::string error;
  if (!rp::bench::WriteChartPNG(rp::bench::OutputDirectory() + "/" + file, series, options, error))
    std::cerr << file << ": " << error << "\n";
}

void BM_HapticTickWithFourFixtures(benchmark::State& state) {
  static const HapticWorld world;
  auto constraints = rp::MakeFixtureConstraints(world.Fixtures);
  rp::HapticRenderer renderer;
  renderer.SetScene(world.Scene.get());
  renderer.Reset(HandAt(0));
  int i = 0;
  for (auto _ : state) renderer.Update(HandAt(++i % 8000), 0.001, constraints.get());
}
BENCHMARK(BM_HapticTickWithFourFixtures)->Unit(benchmark::kMicrosecond);


// ---- the figures
struct Figures {
  nlohmann::json Doc;
  std::vector<std::vector<double>> Accuracy;  // the accuracy table's rows
};

rp::bench::Series Named(const std::string& name, bool points = false) { return {name, {}, {}, points}; }

// The tick with and without the fixtures, both servos: JSON, CSV, a bar chart.
void TickFiguresBothServos(Figures& f, bool quick) {
  const HapticWorld world;
  const int ticks = quick ? 1000 : 8000;
  const TickFigures bare = HapticTicks(world, false, ticks), fixed = HapticTicks(world, true, ticks),
                    vtk = VtkDistanceTicks(world, ticks);
  f.Doc["haptics"] = {{"withoutFixtures", Json(bare)}, {"withFourFixtures", Json(fixed)},
                      {"vtkDistancesOnly", Json(vtk)}, {"targetTickP99Us", 100}};
  // The drilling tick at 0.2 mm (a quick run: 0.3 mm) with all four fixtures, and without.
  const double voxel = quick ? 0.3 : 0.2;
  auto vessel = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  vessel->Build(rp::shapes::Sphere({6.5, 0, -15}, 2, 4), error);
  const Execution drillBare = Drill(voxel, nullptr, 2.5, 1, 0.2, 1.0, vessel);
  const Execution drillFour = Drill(voxel, DrillFixtures(true, true, true, true, 0, vessel), 2.5, 1, 0.2, 1.0, vessel);
  f.Doc["drilling"] = {{"voxelMm", voxel}, {"withoutFixtures", Json(drillBare)}, {"withFourFixtures", Json(drillFour)},
                       {"targetTickP99Us", 100}};
  const std::string dir = rp::bench::OutputDirectory();
  std::vector<std::vector<double>> rows;
  rows.push_back({0, 0, bare.P50, bare.P99, bare.Max, double(bare.Ticks)});
  rows.push_back({0, 4, fixed.P50, fixed.P99, fixed.Max, double(fixed.Ticks)});
  rows.push_back({1, 0, drillBare.Tick.P50, drillBare.Tick.P99, drillBare.Tick.Max, double(drillBare.Tick.Ticks)});
  rows.push_back({1, 4, drillFour.Tick.P50, drillFour.Tick.P99, drillFour.Tick.Max, double(drillFour.Tick.Ticks)});
  rp::bench::WriteCSV(dir + "/guidance_ticks.csv",
                      {"drilling", "fixtures", "tickP50Us", "tickP99Us", "tickMaxUs", "ticks"}, rows, error);
  rp::bench::Series without = Named("without fixtures: p99"), with = Named("four fixtures: p99");
  without.Y = {bare.P99, drillBare.Tick.P99};
  with.Y = {fixed.P99, drillFour.Tick.P99};
  rp::bench::ChartOptions options;
  options.Title = "Servo tick p99 with and without the four virtual fixtures (thread CPU, us; target 100)";
  options.YLabel = "tick p99 (us)";
  rp::bench::WriteBarChartPNG(dir + "/guidance_ticks.png", {"haptics", "drilling"}, {without, with}, options, error);
}

// The three executions of the same plan under the same hand (the demo's ways, run by the demo's
// function): free hand; axis guidance + depth stop; guidance + a forbidden region around a vessel
// beside the tunnel (a structure at risk of the plan, margin 1 mm).
void ThreeExecutions(Figures& f) {
  rp::PlanSnapshot plan;
  rp::TrajectorySnapshot tunnel;
  tunnel.NodeID = tunnel.Name = "plan";
  tunnel.Entry = DrillPlan.Entry();
  tunnel.Target = DrillPlan.Target();
  tunnel.ToolDiameterMm = 4;
  plan.Trajectories.push_back(tunnel);
  rp::StructureAtRiskSnapshot vessel;
  vessel.NodeID = vessel.Name = "vessel";
  vessel.SafetyMarginMm = 1.0;
  vessel.Surface = std::make_shared<const rp::TriangleMesh>(rp::shapes::Sphere({6.5, 0, -15}, 2, 4));
  auto signedDistance = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  signedDistance->Build(*vessel.Surface, error);
  vessel.Signed = signedDistance;
  plan.StructuresAtRisk.push_back(vessel);
  for (const rp::ExecutionWay& way : rp::ExecutionWays()) {
    vtkNew<vtkRPScene> scene;
    vtkNew<vtkRPDrillingLogic> logic;
    logic->SetScene(scene);
    logic->SetTouchOtherModels(false);
    rp::PlanFixtureChoice choice;
    rp::GuidedDrillOptions o;
    o.BurrRadiusMm = 2;
    o.SpeedMmPerS = 2.5;
    o.FeedRate = 8;
    o.Noise.TremorMm = 0.2;
    o.Noise.DriftMmPerS = 1.0;
    o.Noise.Seed = 3;
    rp::GuidedDrillResult r;
    if (!logic->BuildBlockBone({-15, -15, -40}, {15, 15, 0}, 0, 0.3, error) ||
        !rp::ParseFixtureKinds(way.Fixtures, choice, error) ||
        !rp::DrillPlannedTrajectory(logic, plan, tunnel, choice, o, r, error)) {
      std::cerr << way.Name << ": " << error << "\n";
      continue;
    }
    nlohmann::json e = rp::GuidedDrillJson(r);
    e["name"] = way.Name;
    e["fixtures"] = way.Fixtures;
    e["servo"] = Json(FiguresOf(r.Run.TickCompute, r.Run.Ticks));
    f.Doc["executions"].push_back(e);
  }
}

// Accuracy: free against guided over seeds, against stiffness, against drilling time.
void AccuracyFigures(Figures& f, bool quick) {
  rp::bench::Series freeEntry = Named("free hand: entry", true), freeTip = Named("free hand: tip", true);
  rp::bench::Series guidedEntry = Named("guided: entry", true), guidedTip = Named("guided: tip", true);
  for (int s : quick ? std::vector<int>{1} : std::vector<int>{1, 2, 3, 4, 5}) {
    const Execution free = Drill(0.3, DrillFixtures(false, false, false, false, 0, nullptr), 2.5, uint64_t(s));
    const Execution guided = Drill(0.3, DrillFixtures(true, true, false, false, 0, nullptr), 2.5, uint64_t(s));
    f.Doc["accuracy"]["free"].push_back(Json(free));
    f.Doc["accuracy"]["guided"].push_back(Json(guided));
    for (const auto* e : {&free, &guided})
      f.Accuracy.push_back({double(s), e == &guided ? 1.0 : 0.0, e->Entry, e->Tip, e->Angle, e->Depth, e->Seconds});
    freeEntry.X.push_back(s), freeEntry.Y.push_back(free.Entry), freeTip.X.push_back(s), freeTip.Y.push_back(free.Tip);
    guidedEntry.X.push_back(s), guidedEntry.Y.push_back(guided.Entry), guidedTip.X.push_back(s), guidedTip.Y.push_back(guided.Tip);
  }
  Chart("guidance_accuracy_by_seed.png", "Entry and tip offset, free hand vs axis guidance + depth stop (0.2 mm tremor, 1 mm/s drift)",
        "seed", "offset (mm)", {freeEntry, freeTip, guidedEntry, guidedTip});
  rp::bench::Series kEntry = Named("entry"), kTip = Named("tip"), kAngle = Named("angle (deg)");
  for (double k : quick ? std::vector<double>{0.2, 0.6} : std::vector<double>{0.05, 0.1, 0.2, 0.35, 0.5, 0.7}) {
    const Execution g = Drill(0.3, DrillFixtures(true, true, false, false, k, nullptr), 2.5, 3);
    f.Doc["accuracyAgainstStiffness"].push_back({{"stiffnessNPerMm", k}, {"execution", Json(g)}});
    kEntry.X.push_back(k), kEntry.Y.push_back(g.Entry), kTip.X.push_back(k), kTip.Y.push_back(g.Tip);
    kAngle.X.push_back(k), kAngle.Y.push_back(g.Angle);
  }
  Chart("guidance_accuracy_vs_stiffness.png", "Accuracy against axis guidance stiffness (seed 3)", "stiffness (N/mm)",
        "offset (mm) / angle (deg)", {kEntry, kTip, kAngle});
  rp::bench::Series tEntry = Named("entry"), tTip = Named("tip"), tDepth = Named("depth overshoot");
  for (double speed : quick ? std::vector<double>{2.5, 10.0} : std::vector<double>{1.0, 2.0, 5.0, 10.0}) {
    const Execution g = Drill(0.3, DrillFixtures(true, true, false, false, 0, nullptr), speed, 3);
    f.Doc["accuracyAgainstSpeed"].push_back({{"speedMmPerS", speed}, {"execution", Json(g)}});
    tEntry.X.push_back(g.Seconds), tEntry.Y.push_back(g.Entry), tTip.X.push_back(g.Seconds), tTip.Y.push_back(g.Tip);
    tDepth.X.push_back(g.Seconds), tDepth.Y.push_back(std::max(0.0, g.Depth));
  }
  Chart("guidance_accuracy_vs_time.png", "Accuracy against drilling time (axis guidance + depth stop)", "drilling time (s)",
        "mm", {tEntry, tTip, tDepth});
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  const bool quick = rp::bench::QuickRun();
  Figures f;
  TickFiguresBothServos(f, quick);
  ThreeExecutions(f);
  AccuracyFigures(f, quick);
  const std::string dir = rp::bench::OutputDirectory();
  std::string error;
  rp::bench::WriteCSV(dir + "/guidance_accuracy.csv",
                      {"seed", "guided", "entryOffsetMm", "tipOffsetMm", "angleDeg", "depthErrorMm", "drillSeconds"},
                      f.Accuracy, error);
  rp::bench::FinishConditions(dir, "rpGuidanceBenchmark");
  rp::bench::WriteFiguresJSON(dir + "/guidance_benchmark.json", f.Doc, error);
  std::cout << f.Doc.dump(2) << "\n";
  benchmark::Shutdown();
  return 0;
}
