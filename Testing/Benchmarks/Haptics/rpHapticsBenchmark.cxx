// Haptics benchmarks.
//  * Closest point on a 1.3M-triangle sphere: our BVH vs vtkStaticCellLocator::FindClosestPoint
//    (what a VTK user would call each tick) vs a brute-force scan, in the same run.
//  * Per-tick compute of the full renderer (god-object, friction, shading, gain limits,
//    passivity, clamp) on that mesh: distribution (p50/p99/max), 1 and 3 tool points.
//  * Servo period jitter at 1 kHz for ROBOPLAN_HAPTICS_JITTER_SECONDS (default 60) while a busy
//    thread loads the other core, sleeping to the deadline and sleeping + 100 µs spin:
//    period histograms, missed deadlines.
//  * Stiffness against penetration error and stability: a device (mass, own damping) pushed
//    with 2 N onto a sampled virtual wall, simulated in continuous time; Colgate margin.
// Figures (JSON, CSV) and charts (PNG; without a display on a private Xvfb, rpXDisplay.h) go to
// $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output. A quick run (ROBOPLAN_BENCHMARK_QUICK): a
// 5,120-triangle sphere, 0.3 s jitter runs, three stiffnesses.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpHapticServo.h"
#include "rpSimulatedDevice.h"

using rp::Vec3;

namespace {

constexpr double kRadius = 50;
// 20 * 4^8 = 1,310,720 triangles (a quick run, rpBenchmarkConditions.h: 20 * 4^4 = 5,120).
int Level() { return rp::bench::QuickRun() ? 4 : 8; }

struct World {
  std::unique_ptr<rp::HapticScene> Scene;
  vtkSmartPointer<vtkPolyData> Poly;
  vtkNew<vtkStaticCellLocator> Locator;
  std::vector<Vec3> Queries;  // HIP positions along the exploration path
  double BvhBuildS = 0, LocatorBuildS = 0;
};

// The HIP path: a great circle 1 mm under the surface at 100 mm/s with a 1 Hz in/out of ±1.5 mm.
rp::Pose At(const Vec3& p) {
  rp::Pose pose;
  pose.T = p;
  return pose;
}

Vec3 PathPoint(double t) {
  const double angle = 100.0 / kRadius * t;
  const double depth = 1.0 + 1.5 * std::sin(2 * M_PI * t);
  const Vec3 u{std::cos(angle), std::sin(angle) * std::cos(0.3), std::sin(angle) * std::sin(0.3)};
  return u * (kRadius - depth);
}

World& TheWorld() {
  static World* world = [] {
    auto* w = new World;
    const rp::TriangleMesh mesh = rp::shapes::Sphere({0, 0, 0}, kRadius, Level());
    std::cerr << "[haptics-bench] building the " << mesh.Triangles.size() << "-triangle sphere...\n";
    std::vector<std::string> warnings;
    std::string error;
    auto t0 = std::chrono::steady_clock::now();
    w->Scene = rp::HapticScene::Build({{"sphere", "bone", mesh}}, rp::MaterialTable::Defaults(), warnings, error);
    w->BvhBuildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    w->Poly = rp::TriangleMeshToPolyData(mesh);
    t0 = std::chrono::steady_clock::now();
    w->Locator->SetDataSet(w->Poly);
    w->Locator->BuildLocator();
    w->LocatorBuildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int queries = rp::bench::QuickRun() ? 2000 : 20000;
    for (int i = 0; i < queries; ++i) w->Queries.push_back(PathPoint(i * 1e-3));
    return w;
  }();
  return *world;
}

double BruteForceClosest(const rp::TriangleMesh& m, const Vec3& p) {
  double best = HUGE_VAL;
  for (const auto& t : m.Triangles) {
    double bary[3];
    const Vec3 q = rp::BVH::ClosestPointOnTriangle(p, m.Points[t[0]], m.Points[t[1]], m.Points[t[2]], bary);
    best = std::min(best, rp::Norm2(q - p));
  }
  return best;
}

// ---- Google Benchmark cases
void BM_ClosestPoint_BVH(benchmark::State& state) {
  World& w = TheWorld();
  size_t i = 0;
  rp::ClosestPointHit hit;
  for (auto _ : state) {
    w.Scene->Tree.ClosestPoint(w.Queries[i++ % w.Queries.size()], HUGE_VAL, hit);
    benchmark::DoNotOptimize(hit);
  }
}
BENCHMARK(BM_ClosestPoint_BVH);

void BM_ClosestPoint_VTKStaticCellLocator(benchmark::State& state) {
  World& w = TheWorld();
  vtkNew<vtkGenericCell> cell;
  size_t i = 0;
  double closest[3], d2;
  vtkIdType cellId;
  int subId;
  for (auto _ : state) {
    const Vec3& q = w.Queries[i++ % w.Queries.size()];
    const double x[3] = {q.x, q.y, q.z};
    w.Locator->FindClosestPoint(x, closest, cell, cellId, subId, d2);
    benchmark::DoNotOptimize(d2);
  }
}
BENCHMARK(BM_ClosestPoint_VTKStaticCellLocator);

void BM_ClosestPoint_BruteForce(benchmark::State& state) {
  World& w = TheWorld();
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(BruteForceClosest(w.Scene->Mesh, w.Queries[i++ % w.Queries.size()]));
}
BENCHMARK(BM_ClosestPoint_BruteForce)->Iterations(20)->Unit(benchmark::kMillisecond);

void BM_SegmentFirstHit_BVH(benchmark::State& state) {
  World& w = TheWorld();
  size_t i = 0;
  rp::SegmentHit hit;
  for (auto _ : state) {
    const Vec3& q = w.Queries[i++ % w.Queries.size()];
    w.Scene->Tree.FirstHit(q * 1.1, q, rp::BVH::Faces::FrontOnly, hit);
    benchmark::DoNotOptimize(hit);
  }
}
BENCHMARK(BM_SegmentFirstHit_BVH);

void BM_RendererTick(benchmark::State& state) {
  World& w = TheWorld();
  rp::HapticRenderer r;
  const Vec3 points[3] = {{0, 0, 0}, {0, 0, 10}, {0, 0, 20}};
  r.SetToolPoints(points, static_cast<int>(state.range(0)));
  r.SetScene(w.Scene.get());
  size_t i = 0;
  for (auto _ : state) {
    rp::Pose pose;
    pose.T = w.Queries[i++ % w.Queries.size()];
    benchmark::DoNotOptimize(r.Update(pose).Force);
  }
}
BENCHMARK(BM_RendererTick)->Arg(1)->Arg(3);

// ---- distributions, jitter, stiffness sweep (custom main)
struct Distribution {
  double P50 = 0, P99 = 0, Max = 0, Mean = 0;
  size_t Count = 0;
};
Distribution Summarize(std::vector<double> us) {
  Distribution d;
  if (us.empty()) return d;
  std::sort(us.begin(), us.end());
  d.Count = us.size();
  d.P50 = us[us.size() / 2];
  d.P99 = us[std::min(us.size() - 1, static_cast<size_t>(std::ceil(0.99 * us.size())) - 1)];
  d.Max = us.back();
  for (double v : us) d.Mean += v / us.size();
  return d;
}
nlohmann::json Json(const Distribution& d) {
  return {{"count", d.Count}, {"p50Us", d.P50}, {"p99Us", d.P99}, {"maxUs", d.Max}, {"meanUs", d.Mean}};
}
// Wall-clock time of each call; with `cpu`, the calling thread's CPU time instead (time the
// thread was preempted by other processes on this shared machine is then excluded).
template <typename F>
std::vector<double> TimeEach(size_t n, F&& f, bool cpu = false) {
  std::vector<double> us;
  us.reserve(n);
  const clockid_t clock = cpu ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC;
  timespec a, b;
  for (size_t i = 0; i < n; ++i) {
    clock_gettime(clock, &a);
    f(i);
    clock_gettime(clock, &b);
    us.push_back((b.tv_sec - a.tv_sec) * 1e6 + (b.tv_nsec - a.tv_nsec) * 1e-3);
  }
  return us;
}

nlohmann::json PerTickDistributions(const std::string& out) {
  World& w = TheWorld();
  const size_t n = w.Queries.size();
  rp::ClosestPointHit hit;
  const auto bvh = TimeEach(n, [&](size_t i) { w.Scene->Tree.ClosestPoint(w.Queries[i], HUGE_VAL, hit); });
  vtkNew<vtkGenericCell> cell;
  double closest[3], d2;
  vtkIdType cellId;
  int subId;
  const auto vtk = TimeEach(n, [&](size_t i) {
    const double x[3] = {w.Queries[i].x, w.Queries[i].y, w.Queries[i].z};
    w.Locator->FindClosestPoint(x, closest, cell, cellId, subId, d2);
  });
  const auto bvhCpu = TimeEach(n, [&](size_t i) { w.Scene->Tree.ClosestPoint(w.Queries[i], HUGE_VAL, hit); }, true);
  const auto vtkCpu = TimeEach(n, [&](size_t i) {
    const double x[3] = {w.Queries[i].x, w.Queries[i].y, w.Queries[i].z};
    w.Locator->FindClosestPoint(x, closest, cell, cellId, subId, d2);
  }, true);
  double sink = 0;
  const auto brute = TimeEach(30, [&](size_t i) { sink += BruteForceClosest(w.Scene->Mesh, w.Queries[i * std::min<size_t>(600, n / 30)]); });
  benchmark::DoNotOptimize(sink);
  nlohmann::json ticks;
  std::vector<double> tick1;
  for (int points : {1, 3}) {
    rp::HapticRenderer r;
    const Vec3 tool[3] = {{0, 0, 0}, {0, 0, 10}, {0, 0, 20}};
    r.SetToolPoints(tool, points);
    r.SetScene(w.Scene.get());
    rp::Pose pose;
    pose.T = w.Queries[0] * 1.2;
    r.Reset(pose);
    int contacts = 0;
    const auto us = TimeEach(n, [&](size_t i) {
      pose.T = w.Queries[i];
      contacts += r.Update(pose).Contacts > 0;
    });
    r.Reset(pose);
    const auto cpu = TimeEach(n, [&](size_t i) { r.Update(At(w.Queries[i])); }, true);
    if (points == 1) tick1 = us;
    const std::string key = std::to_string(points) + "Point";
    ticks[key] = Json(Summarize(us));
    ticks[key]["threadCpu"] = Json(Summarize(cpu));
    ticks[key]["contactFraction"] = static_cast<double>(contacts) / n;
  }
  // Accuracy of the closest-point answers (same query set): BVH vs the locator.
  double maxDiff = 0;
  for (size_t i = 0; i < std::min<size_t>(n, 2000); ++i) {
    w.Scene->Tree.ClosestPoint(w.Queries[i], HUGE_VAL, hit);
    const double x[3] = {w.Queries[i].x, w.Queries[i].y, w.Queries[i].z};
    w.Locator->FindClosestPoint(x, closest, cell, cellId, subId, d2);
    maxDiff = std::max(maxDiff, std::fabs(std::sqrt(hit.Distance2) - std::sqrt(d2)));
  }
  const Distribution b = Summarize(bvh), v = Summarize(vtk), f = Summarize(brute);
  nlohmann::json doc = {{"triangles", w.Scene->Tree.NumberOfTriangles()},
                        {"bvhBuildSeconds", w.BvhBuildS},
                        {"vtkStaticCellLocatorBuildSeconds", w.LocatorBuildS},
                        {"closestPoint", {{"bvh", Json(b)}, {"vtkStaticCellLocator", Json(v)}, {"bruteForce", Json(f)}}},
                        {"closestPointThreadCpu", {{"bvh", Json(Summarize(bvhCpu))}, {"vtkStaticCellLocator", Json(Summarize(vtkCpu))}}},
                        {"speedupP99VsVTK", v.P99 / b.P99},
                        {"speedupP50VsVTK", v.P50 / b.P50},
                        {"speedupP50VsBruteForce", f.P50 / b.P50},
                        {"maxDistanceDifferenceVsVTKmm", maxDiff},
                        {"rendererTick", ticks}};
  std::string error;
  rp::bench::WriteCSV(out + "/haptics_closest_point.csv", {"method", "p50_us", "p99_us", "max_us"},
                      {{0, b.P50, b.P99, b.Max}, {1, v.P50, v.P99, v.Max}, {2, f.P50, f.P99, f.Max}}, error);
  // Histogram of the 1-point tick compute time.
  std::vector<double> centers, counts;
  for (int i = 0; i < 60; ++i) {
    centers.push_back(0.5 * i + 0.25);
    counts.push_back(0);
  }
  for (double u : tick1) counts[std::min<size_t>(59, static_cast<size_t>(u / 0.5))] += 1;
  rp::bench::ChartOptions o;
  o.Title = "Haptic tick compute, " + std::to_string(w.Scene->Tree.NumberOfTriangles()) + " triangles (1 point)";
  o.XLabel = "compute time (us)";
  o.YLabel = "ticks";
  o.LogY = true;
  rp::bench::WriteHistogramPNG(out + "/haptics_tick_histogram.png", centers, counts, o, error);
  return doc;
}

nlohmann::json Jitter(const std::string& out, double seconds, double spinUs) {
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::vector<double> t;
  std::vector<Vec3> p;
  for (int i = 0; i <= static_cast<int>(seconds * 100) + 100; ++i) {
    t.push_back(i * 0.01);
    p.push_back(PathPoint(i * 0.01));
  }
  std::string error;
  path->Set(t, p, error);
  device.SetTrajectory(path);
  rp::HapticServo servo(device);
  std::vector<std::string> warnings;
  servo.Scenes().Publish(rp::HapticScene::Build({{"sphere", "bone", rp::shapes::Sphere({0, 0, 0}, kRadius, Level())}},
                                                rp::MaterialTable::Defaults(), warnings, error));
  // The other core is busy.
  std::atomic<bool> stop{false};
  std::thread busy([&] {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(1, &set);
    pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    volatile double x = 1;
    while (!stop.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
  });
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.CpuAffinity = 0;
  options.SpinUs = spinUs;
  if (!loop.Start(&servo, options, error)) {
    std::cerr << error << "\n";
    stop = true;
    busy.join();
    return {};
  }
  std::cerr << "[haptics-bench] servo jitter run: " << seconds << " s at 1 kHz, spin " << spinUs << " us ("
            << loop.PriorityNote() << ")\n";
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  loop.Stop();
  stop = true;
  busy.join();
  const rp::ServoStats s = loop.Stats();
  // |period - 1 ms| percentile from the period histogram (1 µs bins).
  const rp::TimingHistogram& h = loop.PeriodHistogram();
  std::vector<double> centers, counts;
  uint64_t total = 0;
  std::vector<uint64_t> deviation(20000, 0);
  for (size_t i = 0; i < h.BinCount(); ++i) {
    const uint64_t c = h.BinValue(i);
    total += c;
    const size_t dev = static_cast<size_t>(std::llabs(static_cast<long long>(i) - 1000));
    deviation[std::min<size_t>(dev, deviation.size() - 1)] += c;
    if (i >= 900 && i <= 1100) {
      centers.push_back(i + 0.5);
      counts.push_back(static_cast<double>(c));
    }
  }
  double jitterP99 = 0, jitterP999 = 0;
  uint64_t seen = 0;
  for (size_t i = 0; i < deviation.size(); ++i) {
    seen += deviation[i];
    if (jitterP99 == 0 && seen >= 0.99 * total) jitterP99 = i + 1;
    if (jitterP999 == 0 && seen >= 0.999 * total) {
      jitterP999 = i + 1;
      break;
    }
  }
  rp::bench::ChartOptions o;
  o.Title = "Servo period at 1 kHz, other core busy";
  o.XLabel = "period (us)";
  o.YLabel = "ticks";
  o.LogY = true;
  o.Title += spinUs > 0 ? " (sleep + " + std::to_string(static_cast<int>(spinUs)) + " us spin)" : " (sleep only)";
  const std::string png = out + "/haptics_period_histogram" + (spinUs > 0 ? "_spin" : "") + ".png";
  rp::bench::WriteHistogramPNG(png, centers, counts, o, error);
  auto stats = [](const rp::TimingStats& t) {
    return nlohmann::json{{"p50Us", t.P50Us}, {"p99Us", t.P99Us}, {"p999Us", t.P999Us}, {"maxUs", t.MaxUs}, {"meanUs", t.MeanUs}};
  };
  return {{"seconds", seconds},
          {"spinUs", spinUs},
          {"ticks", s.Ticks},
          {"realTimePriority", s.RealTimePriority},
          {"period", stats(s.Period)},
          {"periodJitterP99Us", jitterP99},
          {"periodJitterP999Us", jitterP999},
          {"lateness", stats(s.Lateness)},
          {"compute", stats(s.Compute)},
          {"missedDeadlines", s.MissedDeadlines},
          {"overruns", s.Overruns}};
}

// A device of mass m and own damping b pushed onto a sampled wall with a constant hand force,
// integrated in continuous time (1 µs steps) while the renderer runs at 1 kHz (zero-order hold).
struct WallRun {
  double MeanDepth = 0, PeakToPeak = 0;
};
WallRun SimulateWall(double k, bool limitGains, double handForce) {
  const double mass = 4.5e-5;     // N·s²/mm (45 g at the tip)
  const double bDevice = 0.003;   // N·s/mm
  rp::MaterialTable table;
  table.Add({"wall", k, 0.0, 0, 0});
  std::vector<std::string> warnings;
  std::string error;
  auto scene = rp::HapticScene::Build({{"floor", "wall", rp::shapes::Box({-50, -50, -30}, {50, 50, 0})}}, table,
                                      warnings, error);
  rp::HapticRenderer r;
  rp::RendererOptions o;
  o.Friction = false;
  o.ForceShading = false;
  o.PassivityControl = false;
  o.LimitGains = limitGains;
  r.SetOptions(o);
  rp::DeviceInfo device;
  device.MaxForce = 1e6;  // no clamp: show the wall's own behaviour
  device.PhysicalDamping = bDevice;
  device.NominalMaxStiffness = 1e6;
  r.SetDevice(device);
  r.SetScene(scene.get());
  double z = 0.5, v = 0;
  rp::Pose pose;
  pose.T = {0, 0, z};
  r.Reset(pose);
  Vec3 force{};
  const int sub = 1000;
  const double dt = 1e-3 / sub;
  std::vector<double> tail;
  for (int tick = 0; tick < 3000; ++tick) {
    pose.T = {0, 0, z};
    force = r.Update(pose).Force;
    for (int i = 0; i < sub; ++i) {
      const double a = (force.z - handForce - bDevice * v) / mass;
      v += a * dt;
      z += v * dt;
    }
    if (!std::isfinite(z) || std::fabs(z) > 1e3) return {HUGE_VAL, HUGE_VAL};
    if (tick >= 2000) tail.push_back(-z);
  }
  WallRun run;
  for (double d : tail) run.MeanDepth += d / tail.size();
  run.PeakToPeak = *std::max_element(tail.begin(), tail.end()) - *std::min_element(tail.begin(), tail.end());
  return run;
}

nlohmann::json StiffnessSweep(const std::string& out) {
  const double handForce = 2.0, period = 1e-3, bDevice = 0.003;
  rp::bench::Series analytic{"penetration F/k (analytic)", {}, {}, false};
  rp::bench::Series measured{"penetration, simulated (no limit)", {}, {}, true};
  rp::bench::Series limited{"penetration, simulated (gain limit on)", {}, {}, true};
  rp::bench::Series margin{"Colgate margin b - KT/2 (N s/m)", {}, {}, false};
  rp::bench::Series oscillation{"oscillation p-p, no limit (mm)", {}, {}, true};
  rp::bench::Series oscillationLimited{"oscillation p-p, gain limit on (mm)", {}, {}, true};
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::vector<double>> csv;
  const std::vector<double> stiffnesses = rp::bench::QuickRun() ? std::vector<double>{0.5, 2.0, 8.0}
                                                                 : std::vector<double>{0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0,
                                                                                       3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0};
  for (double k : stiffnesses) {
    const WallRun free = SimulateWall(k, false, handForce);
    const WallRun safe = SimulateWall(k, true, handForce);
    const double colgate = (bDevice - k * period / 2) * 1000;  // N·s/m for readability
    analytic.X.push_back(k);
    analytic.Y.push_back(handForce / k);
    margin.X.push_back(k);
    margin.Y.push_back(colgate);
    if (std::isfinite(free.MeanDepth)) {
      measured.X.push_back(k);
      measured.Y.push_back(free.MeanDepth);
      oscillation.X.push_back(k);
      oscillation.Y.push_back(std::max(free.PeakToPeak, 1e-6));
    }
    limited.X.push_back(k);
    limited.Y.push_back(safe.MeanDepth);
    oscillationLimited.X.push_back(k);
    oscillationLimited.Y.push_back(std::max(safe.PeakToPeak, 1e-6));
    rows.push_back({{"stiffness", k}, {"analyticDepth", handForce / k}, {"depthNoLimit", free.MeanDepth},
                    {"oscillationNoLimit", free.PeakToPeak}, {"depthLimited", safe.MeanDepth},
                    {"oscillationLimited", safe.PeakToPeak}, {"colgateMarginNsPerM", colgate}});
    csv.push_back({k, handForce / k, free.MeanDepth, free.PeakToPeak, safe.MeanDepth, safe.PeakToPeak, colgate});
  }
  std::string error;
  rp::bench::WriteCSV(out + "/haptics_stiffness_sweep.csv",
                      {"stiffness_N_per_mm", "depth_analytic_mm", "depth_nolimit_mm", "oscillation_nolimit_mm",
                       "depth_limited_mm", "oscillation_limited_mm", "colgate_margin_Ns_per_m"},
                      csv, error);
  rp::bench::ChartOptions o;
  o.Title = "Stiffness vs penetration error (2 N push, 1 kHz)";
  o.XLabel = "stiffness k (N/mm)";
  o.YLabel = "penetration (mm)";
  o.LogX = true;
  o.LogY = true;
  rp::bench::WriteChartPNG(out + "/haptics_stiffness_penetration.png", {analytic, measured, limited}, o, error);
  o.Title = "Stiffness vs stability (device b = 3 N s/m, T = 1 ms)";
  o.YLabel = "margin (N s/m) / oscillation (mm)";
  o.LogY = false;
  rp::bench::WriteChartPNG(out + "/haptics_stiffness_stability.png", {margin, oscillation, oscillationLimited}, o, error);
  return {{"handForceN", handForce}, {"deviceDampingNsPerMm", bDevice}, {"periodS", period},
          {"colgateLimitNPerMm", 2 * bDevice / period}, {"rows", rows}};
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  const std::string out = rp::bench::OutputDirectory();
  const char* env = std::getenv("ROBOPLAN_HAPTICS_JITTER_SECONDS");
  const double seconds = env ? std::atof(env) : rp::bench::QuickRun() ? 0.3 : 60.0;
  nlohmann::json doc;
  doc["perTick"] = PerTickDistributions(out);
  doc["stiffnessSweep"] = StiffnessSweep(out);
  if (seconds > 0) {
    doc["jitter"] = Jitter(out, seconds, 0);
    doc["jitterSpin"] = Jitter(out, seconds, 100);
  }
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpHapticsBenchmark");  // the load after, the steal over the run
  std::string error;
  rp::bench::WriteFiguresJSON(out + "/haptics_benchmark.json", doc, error);
  std::cout << doc.dump(2) << "\n";
  benchmark::Shutdown();
  return 0;
}
