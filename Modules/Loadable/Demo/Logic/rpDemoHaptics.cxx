// Demo stage: haptic exploration of the knee at 1 kHz with the simulated device (seed 2.2,
// 3.2.1, Figure 5). Two passes, as a trainee toggles tissue layers: the soft tissue from
// outside, then the bones with the soft tissue hidden. Each pass presses into surfaces found by
// casting rays from the front (anterior), holds, and retracts.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>

#include <vtkNew.h>

#include "rpBenchmarkChart.h"
#include "rpDemoStages.h"
#include "rpDeviceProfiles.h"
#include "rpHapticSceneBridge.h"
#include "rpReport.h"
#include "rpServoLoadReport.h"
#include "rpSimulatedDevice.h"
#include "rpStageRunner.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// Anterior approach to every surface hit on a grid of rays travelling −A (from the front).
std::shared_ptr<WaypointTrajectory> AnteriorProbePath(const HapticScene& scene, int columns, int rows,
                                                      std::string& error) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Vec3& p : scene.Mesh.Points) lo = Min(lo, p), hi = Max(hi, p);
  const double front = hi.y + 10;
  std::vector<double> t;
  std::vector<Vec3> p;
  double now = 0;
  auto go = [&](const Vec3& q, double speed) {
    if (!p.empty()) now += std::fmax(1e-3, Norm(q - p.back()) / speed);
    t.push_back(now);
    p.push_back(q);
  };
  // Keep away from the caps where the structures leave the scanned volume (top and bottom).
  const double zlo = lo.z + 0.25 * (hi.z - lo.z), zhi = hi.z - 0.25 * (hi.z - lo.z);
  go({0.5 * (lo.x + hi.x), front, 0.5 * (zlo + zhi)}, 100);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      const double x = lo.x + (hi.x - lo.x) * (i + 0.5) / columns;
      const double z = zlo + (zhi - zlo) * (j + 0.5) / std::max(1, rows - 1 + (rows == 1));
      SegmentHit hit;
      if (!scene.Tree.FirstHit({x, front, z}, {x, lo.y - 1, z}, BVH::Faces::FrontOnly, hit)) continue;
      const double y = hit.Point.y;
      go({x, y + 8, z}, 150);
      go({x, y - 2.5, z}, 40);       // press 2.5 mm in at 40 mm/s
      go({x, y - 2.5001, z}, 5e-4);  // hold 0.2 s
      go({x, y + 8, z}, 40);
    }
  if (p.size() < 3) {
    error = "no haptic surface in front of the probe";
    return nullptr;
  }
  auto path = std::make_shared<WaypointTrajectory>();
  if (!path->Set(t, p, error)) return nullptr;
  return path;
}

// The seed paper's device: the demo renders what a Phantom Omni can.
constexpr const char* DemoDevice = "omni";

struct PassResult {
  ServoStats Servo;
  MaterialTable Materials;
  std::vector<MaterialClamp> Clamps;
  std::vector<std::string> Warnings;
  std::vector<std::string> TissueNames;
  // Per tissue: penetration (|HIP − proxy|, mm) and force (N) samples, decimated.
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> ForceCurves;
  std::map<std::string, uint64_t> ContactTicks;
  double MaxForce = 0;
  uint64_t Records = 0, Dropped = 0;
  uint32_t WatchdogTrips = 0;
  MachineLoad Load;  // what the machine did to the servo thread over the pass
  std::vector<double> PeriodBinsUs, PeriodCounts;
};

// One pass in the Haptics logic: the Omni's stylus (in RAS) along the anterior probe path.
PassResult RunPass(DemoState& state, const std::string& name, double maxSeconds) {
  std::string error;
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(state.Scene);
  if (!logic->SetDeviceProfile(DemoDevice, error)) throw std::runtime_error(error);
  auto preview = logic->PreviewHapticScene(error);
  if (!preview || preview->Tree.Empty()) throw std::runtime_error(name + ": no haptic models (" + error + ")");
  auto path = AnteriorProbePath(*preview, 4, 3, error);
  if (!path) throw std::runtime_error(name + ": " + error);
  logic->SetSimulatedTrajectory(path);
  logic->SetLogPath((fs::path(state.Output) / ("haptics-" + name + ".csv")).string());
  logic->SetRampSeconds(0.1);
  ServoLoop::Options loop;
  loop.SpinUs = 100;
  logic->SetLoopOptions(loop);
  logic->SetSummarize(true);
  const double seconds = std::min(maxSeconds, path->Duration() + 0.2);
  if (!logic->RunSimulated(seconds, [&](double elapsed) { state.Runner->Progress(std::min(1.0, elapsed / seconds), name); },
                           error))
    throw std::runtime_error(name + ": " + error);
  const HapticSession& session = *logic->GetSession();
  PassResult result;
  result.Servo = session.Scheduler().Stats();
  result.Load = session.Scheduler().Load();
  result.Materials = session.Materials();
  result.Clamps = session.Clamps();
  result.Warnings = session.Warnings();
  result.TissueNames = session.TissueNames();
  result.Dropped = logic->GetSession()->Servo().LogRing().DroppedCount();
  const HapticForceSummary& figures = session.Summary();
  result.Records = figures.Records;
  result.MaxForce = figures.MaxForce;
  auto tissue = [&](int label) {
    return label >= 0 && static_cast<size_t>(label) < result.TissueNames.size() ? result.TissueNames[size_t(label)] : "?";
  };
  for (const auto& [label, ticks] : figures.TissueTicks) result.ContactTicks[tissue(label)] = ticks;
  for (const auto& [label, curve] : figures.ForceCurves) result.ForceCurves[tissue(label)] = curve;
  HapticState last;
  if (logic->GetSession()->Servo().ReadState(last)) result.WatchdogTrips = last.WatchdogTrips;
  const TimingHistogram& hist = session.Scheduler().PeriodHistogram();
  for (size_t i = 0; i < hist.BinCount(); ++i) {
    const double us = (i + 0.5) * hist.BinWidthNs() / 1000.0;
    if (us < 800 || us > 1200) continue;  // around the 1 ms period
    result.PeriodBinsUs.push_back(us);
    result.PeriodCounts.push_back(static_cast<double>(hist.BinValue(i)));
  }
  return result;
}

void SetHaptic(DemoState& state, const std::vector<std::string>& ids, bool haptic) {
  for (const auto& id : ids) {
    if (auto* model = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id))) model->SetHaptic(haptic);
  }
}

}  // namespace

void ExploreHaptically(DemoState& state) {
  const std::string stage = "Haptics";
  if (state.HapticModelIDs.empty()) throw std::runtime_error("no haptic meshes from the segmentation stage");
  std::vector<std::string> softIDs, boneIDs;
  for (const auto& id : state.HapticModelIDs) {
    auto* model = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id));
    if (!model) continue;
    (model->GetTissueClass() == "bone" ? boneIDs : softIDs).push_back(id);
  }
  const double each = std::max(1.0, state.Options.HapticSeconds / 2);
  std::vector<std::pair<std::string, PassResult>> passes;
  if (!softIDs.empty()) {
    SetHaptic(state, boneIDs, false);
    SetHaptic(state, softIDs, true);
    passes.emplace_back("soft-tissue", RunPass(state, "soft-tissue", each));
  }
  SetHaptic(state, softIDs, false);
  SetHaptic(state, boneIDs, true);
  passes.emplace_back("bone", RunPass(state, "bone", each));
  SetHaptic(state, softIDs, true);  // the saved scene has every haptic model on

  std::vector<bench::Series> forceSeries;
  for (const auto& [name, r] : passes) {
    state.Report->AddFigureBelow(stage, name + " pass: servo period p99 jitter", std::abs(r.Servo.Period.P99Us - 1000.0),
                                 "µs", 50.0, std::to_string(r.Servo.Ticks) + " ticks at 1 kHz");
    state.Report->AddFigureBelow(stage, name + " pass: compute time per tick p99", r.Servo.Compute.P99Us, "µs", 20.0);
    state.Report->AddFigureBelow(stage, name + " pass: missed deadlines (> 0.5 ms late)", r.Servo.MissedPercent(), "%",
                                 ServoStats::MissedBudgetPercent + 1e-9,
                                 std::to_string(r.Servo.MissedDeadlines) + " of " + std::to_string(r.Servo.Ticks) +
                                     " ticks (" + (r.Servo.RealTimePriority ? "SCHED_FIFO" : "no real-time priority here") +
                                     "); " + MachineLoadReading(r.Load, r.Servo.MissedDeadlines, r.Servo.Overruns));
    state.Report->AddFigureBelow(stage, name + " pass: maximum force", r.MaxForce, "N", 3.3 + 1e-6,
                                 "device maximum 3.3 N (eq. 6 clamp)");
    for (const std::string& warning : r.Warnings) state.Report->AddNote("Haptics (" + name + " pass): " + warning);
    for (const auto& [tissue, ticks] : r.ContactTicks) {
      state.Report->AddFigure(stage, name + " pass: ticks in contact with " + tissue, static_cast<double>(ticks), "");
      const auto& curve = r.ForceCurves.at(tissue);
      if (!curve.first.empty()) forceSeries.push_back({tissue, curve.first, curve.second, true});
    }
    if (r.ContactTicks.empty()) throw std::runtime_error(name + " pass: the probe never touched a surface");
  }
  // What the table asks against what the Omni renders, and the Touch for comparison (each clamp
  // also a warning in the notes when it bites).
  const std::vector<MaterialClamp>& omni = passes.back().second.Clamps;
  DeviceProfile touch;
  std::string error;
  if (!FindDeviceProfile("touch", touch, error)) throw std::runtime_error(error);
  const std::vector<MaterialClamp> onTouch = ClampMaterials(passes.back().second.Materials.Materials(), touch.Info,
                                                             passes.back().second.Servo.Period.P99Us * 1e-6);
  int clamped = 0;
  for (const MaterialClamp& c : omni) clamped += c.Clamped();
  state.Report->AddFigureBelow(stage, "tissues clamped on the Phantom Omni", clamped, "", 0.5,
                               "stiffness above what the device renders stably (nominal limit, Colgate-Schenkel)");
  if (!CanDrawPicturesOrWarn(state, stage, "haptics charts")) return;
  std::vector<std::string> tissues;
  bench::Series asked{"requested (materials.json)", {}, {}}, onOmni{"rendered: Phantom Omni", {}, {}},
      onTouchBars{"rendered: Touch", {}, {}};
  for (size_t i = 0; i < omni.size() && i < onTouch.size(); ++i) {
    tissues.push_back(omni[i].Tissue);
    asked.Y.push_back(omni[i].RequestedStiffness);
    onOmni.Y.push_back(omni[i].RenderedStiffness);
    onTouchBars.Y.push_back(onTouch[i].RenderedStiffness);
  }
  bench::ChartOptions clampChart{"Stiffness per tissue: requested against rendered", "tissue", "stiffness (N/mm)"};
  state.Report->AddPictureIf(bench::WriteBarChartPNG((fs::path(state.Output) / "haptics-stiffness-clamp.png").string(),
                                                     tissues, {asked, onOmni, onTouchBars}, clampChart, error),
                             stage, "haptics-stiffness-clamp.png",
                             "Stiffness each tissue asks (Resources/Materials/materials.json) and what each device "
                             "renders stably at the measured servo period: lower bars are clamped, with a warning.",
                             error);
  bench::ChartOptions chart{"Force against penetration per tissue (eq. 1-3, clamp eq. 6)", "penetration |HIP − proxy| (mm)",
                            "force (N)"};
  state.Report->AddPictureIf(
      bench::WriteChartPNG((fs::path(state.Output) / "haptics-force-per-tissue.png").string(), forceSeries, chart, error),
      stage, "haptics-force-per-tissue.png",
      "Force against penetration for each tissue touched: the slope is the tissue's rendered "
      "stiffness (never above the device's 3.3 N, eq. 6).",
      error);
  for (const auto& [name, r] : passes) {
    if (r.PeriodBinsUs.empty()) continue;
    bench::ChartOptions h{"Servo period histogram (" + name + " pass)", "period (µs)", "ticks"};
    const std::string file = "haptics-period-" + name + ".png";
    state.Report->AddPictureIf(
        bench::WriteHistogramPNG((fs::path(state.Output) / file).string(), r.PeriodBinsUs, r.PeriodCounts, h, error),
        stage, file, "1 kHz servo loop: measured period of every tick (" + name + " pass).", error);
  }
}

}  // namespace rp
