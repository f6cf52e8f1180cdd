// Planning benchmarks: proposing a trajectory's entry, speed against accuracy.
//  * 10 000 entry candidates against 3 structures at risk (icospheres of 20 480 triangles each, a
//    scene the size of a knee's): the clearance of every candidate's tool by our BVH segment query
//    (warm-started, 1 and 2 threads), against the straightforward VTK way in the same run:
//    vtkImplicitPolyDataDistance evaluated along each candidate every `step` mm (0.25, 0.5, 1, 2 mm:
//    slower when finer, and always an over-estimate), timed on 1 000 candidates and scaled to 10 000.
//    Accuracy: the largest difference of each way's clearance from the exact one (ours is exact to
//    rounding; VTK's misses the closest point between its samples).
// Target: 10 000 candidates x 3 structures in under 200 ms on 2 cores (issue 37). Figures (JSON,
// CSV) and a chart (PNG) go to $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>

#include <nlohmann/json.hpp>
#include <vtkImplicitPolyDataDistance.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpTrajectoryProposal.h"

using rp::Vec3;

namespace {

constexpr double ToolDiameter = 4.0;

struct Scene {
  Vec3 Target;
  std::vector<Vec3> Candidates;
  std::vector<rp::StructureAtRiskSnapshot> Structures;
  std::vector<uint32_t> Order;
  double Spacing = 0;
};

rp::StructureAtRiskSnapshot Structure(const std::string& name, rp::TriangleMesh mesh, double margin) {
  rp::StructureAtRiskSnapshot s;
  s.Name = name;
  s.SafetyMarginMm = margin;
  mesh.ComputeNormals();
  auto surface = std::make_shared<rp::TriangleMesh>(std::move(mesh));
  s.Surface = surface;
  auto tree = std::make_shared<rp::BVH>();
  tree->Build(*surface);
  s.Tree = tree;
  auto signedDistance = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  if (signedDistance->Build(*surface, error)) s.Signed = signedDistance;
  return s;
}

// 10 000 entries on a 100 x 100 grid 60 mm above the target; three spheres between them.
const Scene& AnalyticScene() {
  static Scene scene = [] {
    Scene s;
    s.Target = {0, 0, 0};
    for (int j = 0; j < 100; ++j)
      for (int i = 0; i < 100; ++i) s.Candidates.push_back({-20 + 0.4 * i, -20 + 0.4 * j, 60});
    s.Structures.push_back(Structure("sphere A", rp::shapes::Sphere({12, 0, 30}, 5, 5), 2));
    s.Structures.push_back(Structure("sphere B", rp::shapes::Sphere({-10, 8, 25}, 5, 5), 2));
    s.Structures.push_back(Structure("sphere C", rp::shapes::Sphere({0, -12, 35}, 5, 5), 2));
    s.Order = rp::SpatialOrder(s.Candidates);
    s.Spacing = rp::MedianSpacing(s.Candidates);
    return s;
  }();
  return scene;
}

rp::ProposalRequest Request(const Scene& s, int threads) {
  rp::ProposalRequest r;
  r.Target = s.Target;
  r.ToolDiameterMm = ToolDiameter;
  r.Candidates = s.Candidates;
  r.Threads = threads;
  r.Order = &s.Order;
  r.SpacingMm = s.Spacing;
  return r;
}

void BM_Propose_BVH(benchmark::State& state) {
  const Scene& s = AnalyticScene();
  const rp::ProposalRequest request = Request(s, static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const rp::ProposalResult result = rp::ProposeTrajectory(request, s.Structures, nullptr);
    benchmark::DoNotOptimize(result.Best.data());
  }
  state.counters["candidates"] = static_cast<double>(s.Candidates.size());
  state.counters["structures"] = static_cast<double>(s.Structures.size());
}
BENCHMARK(BM_Propose_BVH)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();

// The VTK way: the smallest |distance| of the samples along the candidate's axis, less the radius.
struct VTKWay {
  std::vector<vtkSmartPointer<vtkImplicitPolyDataDistance>> Distances;
  explicit VTKWay(const Scene& s) {
    for (const auto& structure : s.Structures) {
      auto d = vtkSmartPointer<vtkImplicitPolyDataDistance>::New();
      d->SetInput(rp::TriangleMeshToPolyData(*structure.Surface));
      this->Distances.push_back(d);
    }
  }
  double Clearance(const Vec3& entry, const Vec3& target, double step, const Scene& s) const {
    const int n = std::max(1, static_cast<int>(std::ceil(rp::Norm(target - entry) / step)));
    double best = HUGE_VAL;
    for (size_t k = 0; k < this->Distances.size(); ++k)
      for (int i = 0; i <= n; ++i) {
        const Vec3 p = entry + (target - entry) * (static_cast<double>(i) / n);
        best = std::min(best, std::fabs(this->Distances[k]->EvaluateFunction(p.x, p.y, p.z)) - 0.5 * ToolDiameter -
                                  s.Structures[k].SafetyMarginMm);
      }
    return best;
  }
};

void BM_Propose_VTKImplicitPolyDataDistance(benchmark::State& state) {
  const Scene& s = AnalyticScene();
  static const VTKWay vtk(s);
  const double step = state.range(0) / 100.0;
  std::mt19937 rng(5);
  for (auto _ : state) {
    double sum = 0;
    for (int c = 0; c < 1000; ++c) sum += vtk.Clearance(s.Candidates[static_cast<size_t>(rng() % s.Candidates.size())], s.Target, step, s);
    benchmark::DoNotOptimize(sum);
  }
  state.counters["candidates"] = 1000;
  state.counters["stepMm"] = step;
}
BENCHMARK(BM_Propose_VTKImplicitPolyDataDistance)->Arg(25)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMillisecond)->Iterations(1);

double Seconds(const std::function<void()>& f, int repeats) {
  double best = HUGE_VAL;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

// The figures of one scene: our times (1, 2 threads, best of 5), VTK's per step (1 000 candidates,
// scaled to all), and each way's largest clearance error on those candidates against ours.
nlohmann::json MeasureScene(const std::string& name, const Scene& s) {
  nlohmann::json doc = {{"scene", name}, {"candidates", s.Candidates.size()}, {"structures", s.Structures.size()},
                        {"toolDiameterMm", ToolDiameter}};
  std::vector<long> triangles;
  for (const auto& st : s.Structures) triangles.push_back(static_cast<long>(st.Surface->Triangles.size()));
  doc["structureTriangles"] = triangles;
  rp::ProposalResult ours;
  const bool quick = rp::bench::QuickRun();  // checks the figures are written: one repeat, fewer VTK samples
  for (int threads : {1, 2}) {
    const rp::ProposalRequest request = Request(s, threads);
    const double seconds = Seconds([&] { ours = rp::ProposeTrajectory(request, s.Structures, nullptr); }, quick ? 1 : 5);
    doc["ours"].push_back({{"threads", threads}, {"ms", 1000 * seconds}, {"msPer10000", 1000 * seconds * 10000 / s.Candidates.size()}});
  }
  const VTKWay vtk(s);
  std::mt19937 rng(7);
  std::vector<size_t> sample;
  for (int i = 0; i < (quick ? 50 : 1000); ++i) sample.push_back(rng() % s.Candidates.size());
  for (double step : quick ? std::vector<double>{1.0, 2.0} : std::vector<double>{0.25, 0.5, 1.0, 2.0}) {
    double worst = 0;
    const double seconds = Seconds([&] {
      worst = 0;
      for (size_t c : sample) {
        const double v = vtk.Clearance(s.Candidates[c], s.Target, step, s);
        worst = std::max(worst, std::fabs(v - ours.Scores[c].SlackMm));
      }
    }, 1);
    doc["vtk"].push_back({{"stepMm", step}, {"candidatesTimed", sample.size()}, {"msPer1000", 1000 * seconds * 1000 / sample.size()},
                          {"msPer10000", 1000 * seconds * 10000 / sample.size()}, {"maxErrorMm", worst}});
  }
  doc["targetMs"] = 200;
  return doc;
}

void WriteFigures(const nlohmann::json& scenes, const std::string& out) {
  std::vector<rp::bench::Series> series;
  std::vector<std::vector<double>> rows;
  for (const auto& scene : scenes) {
    const std::string name = scene["scene"];
    rp::bench::Series vtk{"vtkImplicitPolyDataDistance every 0.25-2 mm, " + name, {}, {}, false};
    for (const auto& v : scene["vtk"]) {
      vtk.X.push_back(v["msPer10000"]), vtk.Y.push_back(std::max(1e-6, v["maxErrorMm"].get<double>()));
      rows.push_back({v["stepMm"].get<double>(), v["msPer10000"].get<double>(), v["maxErrorMm"].get<double>(), 0});
    }
    series.push_back(vtk);
    for (const auto& o : scene["ours"]) {
      series.push_back({"our BVH, " + std::to_string(o["threads"].get<int>()) + " thread(s), " + name,
                        {o["msPer10000"].get<double>()}, {1e-6}, true});
      rows.push_back({0, o["msPer10000"].get<double>(), 0, o["threads"].get<double>()});
    }
  }
  std::string error;
  rp::bench::WriteCSV(out + "/planning_proposal.csv", {"vtk_step_mm", "ms_per_10000_candidates", "max_error_mm", "our_threads"},
                      rows, error);
  rp::bench::WriteChartPNG(out + "/planning_proposal.png", series,
                           {"Proposing an entry: 10 000 candidates x 3 structures, time against clearance error",
                            "time for 10 000 candidates (ms)", "largest clearance error (mm; ours exact, drawn at 1e-6)",
                            true, true},
                           error);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  const std::string out = rp::bench::OutputDirectory();
  nlohmann::json doc;
  doc["scenes"].push_back(MeasureScene("analytic (3 spheres, 20 480 triangles each)", AnalyticScene()));
  WriteFigures(doc["scenes"], out);
  rp::bench::FinishConditions(out, "rpPlanningBenchmark");  // the load after, the steal over the run
  std::string error;
  rp::bench::WriteFiguresJSON(out + "/planning_benchmark.json", doc, error);
  std::cout << doc.dump(2) << "\n";
  benchmark::Shutdown();
  return 0;
}
