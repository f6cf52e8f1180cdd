// Drilling benchmarks: speed against accuracy of the voxel burr.
//  * Servo tick while drilling a tunnel through a 2 mm cortex into trabecular bone (an analytic
//    long bone, Ø40 × 120 mm), on 0.2 … 0.5 mm grids: thread-CPU time of every tick (p50/p99/max),
//    scripted on one thread (the same ticks as the 1 kHz loop, without the scheduler's noise; the
//    mesh assembled once at the end, as `roboplan drill` does), and the real 1 kHz loop at 0.3 mm
//    (compute and period p99, missed deadlines; a mesh assembled every display frame).
//  * Display: re-contouring the dirty blocks of each 30 Hz frame (p95, blocks per frame) against
//    re-contouring the whole bone in the same run, with our block mesher and the VTK way
//    (vtkFlyingEdges3D on the whole voxel volume, what a VTK user would call each frame), both on
//    VTK's SMP threads (the count and back-end are printed; each the fastest of 3), each with its
//    surface's distance to the true surface (the analytic bone less the tunnel's capsule; mean over the surface).
//  * Accuracy: the removed volume of a straight stroke (r = 2, L = 10 mm) in a homogeneous block
//    against πr²L + 4/3·πr³, on each grid: error against grid size, and time against accuracy.
//  * The real knee CT's tibia (../shared/data/knee-ct-vhf, when present): whole-bone re-contour
//    and a tunnel into it at 0.3 mm.
// Figures (JSON, CSV) and charts (PNG; without a display on a private Xvfb, rpXDisplay.h) go to
// $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpDrillAnalytic.h"
#include "rpDrillBoneBuilder.h"
#include "rpDrillSession.h"
#include "rpSimulatedDevice.h"
#include "rpVolumeFiles.h"
#include "rpVolumeIO.h"

using rp::Vec3;

namespace {

const double Grids[] = {0.2, 0.25, 0.3, 0.35, 0.4, 0.5};

std::vector<rp::Material> Materials() {
  rp::MaterialTable table;
  std::string error;
  if (!rp::LoadMaterialTable(table, error)) std::cerr << error << "\n";
  return rp::DrillableMaterials(table);
}

// A long bone: a capped cylinder along S (radius 20, z in [−60, 60]), 2 mm cortex around
// trabecular bone.
rp::AnalyticBone LongBone(const std::vector<rp::Material>& m) {
  rp::AnalyticBone bone;
  bone.Lo = {-20, -20, -60};
  bone.Hi = {20, 20, 60};
  auto sd = [](const Vec3& p) {
    const double radial = std::sqrt(p.x * p.x + p.y * p.y) - 20, axial = std::fabs(p.z) - 60;
    return std::min(std::max(radial, axial), 0.0) + std::sqrt(std::pow(std::max(radial, 0.0), 2) + std::pow(std::max(axial, 0.0), 2));
  };
  bone.SignedDistance = sd;
  const uint8_t cortical = rp::FindDrillMaterial(m, "bone"), trabecular = rp::FindDrillMaterial(m, "trabecular bone");
  bone.Material = [sd, cortical, trabecular](const Vec3& p) { return sd(p) < -2.0 ? trabecular : cortical; };
  return bone;
}

double Milliseconds(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// How far a contour lies from the true surface (mm). The mean is over the surface (each
// triangle's area times the mean |sd| of its corners), so it does not depend on how a mesher
// stores its vertices: ours keeps each 8³ block's vertices apart (a vertex on a block face is
// stored twice), VTK's flying edges shares them; a mean over stored vertices would weight the
// block faces twice (ours read ~1 % higher that way, with the same triangles). The mean over
// distinct vertex positions and the largest |sd| are given too.
struct SurfaceError {
  double MeanMm = 0, VertexMeanMm = 0, MaxMm = 0;
  size_t Vertices = 0;  // distinct positions
};
using SignedDistanceFunction = std::function<double(const Vec3&)>;

class SurfaceErrorSum {
 public:
  explicit SurfaceErrorSum(SignedDistanceFunction sd) : Sd(std::move(sd)) {}
  // One mesh (or one block of one): xyz per vertex, 3 vertex indices per triangle.
  void Add(const float* xyz, size_t vertices, const uint32_t* triangles, size_t triangleCount) {
    std::vector<double> d(vertices);
    for (size_t i = 0; i < vertices; ++i) {
      const std::array<float, 3> key{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
      d[i] = std::fabs(this->Sd(Vec3{key[0], key[1], key[2]}));
      if (this->Seen.insert(key).second) this->VertexSum += d[i];
      this->Max = std::max(this->Max, d[i]);
    }
    for (size_t t = 0; t < triangleCount; ++t) {
      const uint32_t* c = triangles + 3 * t;
      const float *a = xyz + 3 * c[0], *b = xyz + 3 * c[1], *e = xyz + 3 * c[2];
      const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ae{e[0] - a[0], e[1] - a[1], e[2] - a[2]};
      const double area = 0.5 * rp::Norm(rp::Cross(ab, ae));
      this->AreaSum += area;
      this->WeightedSum += area * (d[c[0]] + d[c[1]] + d[c[2]]) / 3;
    }
  }
  SurfaceError Result() const {
    SurfaceError e;
    e.MeanMm = this->AreaSum > 0 ? this->WeightedSum / this->AreaSum : 0;
    e.Vertices = this->Seen.size();
    e.VertexMeanMm = e.Vertices ? this->VertexSum / double(e.Vertices) : 0;
    e.MaxMm = this->Max;
    return e;
  }

 private:
  SignedDistanceFunction Sd;
  std::set<std::array<float, 3>> Seen;
  double AreaSum = 0, WeightedSum = 0, VertexSum = 0, Max = 0;
};

SurfaceError MeasureSurfaceError(const rp::BlockMesher& mesher, const SignedDistanceFunction& sd) {
  SurfaceErrorSum sum(sd);
  for (const rp::BlockMesh& b : mesher.Blocks())
    sum.Add(b.Points.data(), b.Points.size() / 3, b.Triangles.data(), b.TriangleCount());
  return sum.Result();
}

constexpr int WholeBoneRuns = 3;  // the whole-bone contours, ours and VTK's, are the fastest of 3

// The whole bone contoured the VTK way: the voxels as one dense image, vtkFlyingEdges3D (on VTK's
// SMP threads, as our mesher). Its distance to the surface `sd` goes to `error`.
double WholeBoneVTK(const rp::DrillVolume& volume, size_t& triangles, const SignedDistanceFunction& sd = nullptr,
                    SurfaceError* error = nullptr) {
  const rp::DrillGrid& g = volume.Grid();
  vtkNew<vtkImageData> image;
  image->SetDimensions(g.Dimensions[0], g.Dimensions[1], g.Dimensions[2]);
  image->SetSpacing(g.Spacing, g.Spacing, g.Spacing);
  image->SetOrigin(g.Origin.x, g.Origin.y, g.Origin.z);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* voxels = static_cast<unsigned char*>(image->GetScalarPointer());
  std::fill(voxels, voxels + g.VoxelCount(), 0);
  for (size_t s = 0; s < volume.AllocatedBlocks(); ++s) {
    const auto c = volume.BlockCoordinate(static_cast<int32_t>(s));
    const auto* d = volume.BlockDensities(static_cast<int32_t>(s));
    for (int v = 0; v < rp::DrillVolume::BlockVoxels; ++v) {
      const int i = c[0] * 8 + (v & 7), j = c[1] * 8 + ((v >> 3) & 7), k = c[2] * 8 + (v >> 6);
      if (volume.Contains(i, j, k)) voxels[(size_t(k) * g.Dimensions[1] + j) * g.Dimensions[0] + i] = d[v].load();
    }
  }
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 127.5);
  contour->ComputeNormalsOn();
  double ms = 1e300;
  for (int run = 0; run < WholeBoneRuns; ++run) {
    contour->Modified();
    const auto start = std::chrono::steady_clock::now();
    contour->Update();
    ms = std::min(ms, Milliseconds(start));
  }
  vtkPolyData* mesh = contour->GetOutput();
  triangles = static_cast<size_t>(mesh->GetNumberOfPolys());
  if (error && sd && mesh->GetNumberOfPoints() > 0) {
    vtkNew<vtkFloatArray> xyz;  // the points as floats, as our mesher stores them
    xyz->DeepCopy(mesh->GetPoints()->GetData());
    std::vector<uint32_t> triangles;
    triangles.reserve(3 * size_t(mesh->GetNumberOfPolys()));
    vtkCellArray* polys = mesh->GetPolys();
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
      if (n == 3) triangles.insert(triangles.end(), {uint32_t(ids[0]), uint32_t(ids[1]), uint32_t(ids[2])});
    SurfaceErrorSum sum(sd);
    sum.Add(xyz->GetPointer(0), size_t(mesh->GetNumberOfPoints()), triangles.data(), triangles.size() / 3);
    *error = sum.Result();
  }
  return ms;
}

struct GridFigures {
  double Grid = 0;
  // tunnel in the long bone
  double TickP50 = 0, TickP99 = 0, TickMax = 0;
  uint64_t Ticks = 0;
  double ContourP95 = 0, ContourMax = 0, BlocksMean = 0, AssembleP95 = 0;
  size_t Frames = 0;
  double WholeOursMs = 0, WholeVTKMs = 0;
  size_t WholeTriangles = 0, WholeTrianglesVTK = 0, Blocks = 0;
  SurfaceError WholeError, WholeErrorVTK;  // against the analytic bone minus the tunnel's capsule
  double MemoryMB = 0, Removed = 0;
  // known-answer stroke
  double Expected = 0, StrokeRemoved = 0, ErrorPercent = 0;
};

// The tunnel: from outside the anterior cortex, 30° down into the trabecular core, 25 mm.
const Vec3 TunnelFrom{0.3, 26, 8};
bool Tunnel(rp::DrillVolume& bone, double radius, GridFigures& f, bool realtime, rp::DrillRunResult& result) {
  const Vec3 from = TunnelFrom, to = from + rp::Normalized(Vec3{0, -std::cos(M_PI / 6), -std::sin(M_PI / 6)}) * 25;
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::string error;
  path->Set({0.0, 25 / 10.0}, {from, to}, error);
  device.SetTrajectory(path);
  rp::DrillDisplay display(bone);
  display.Initialize();
  rp::DrillSession session(device, bone, display);
  rp::DrillSession::Options options;
  options.Servo.RampSeconds = 0;
  options.KeepRecords = !realtime;
  options.KeepPath = false;
  options.Loop.RequestRealTimePriority = realtime;
  rp::DrillRunOptions run;
  run.Realtime = realtime;
  run.MaxSeconds = realtime ? 6.0 : 30.0;
  const rp::DrillControl on{true, radius, 60000};
  run.Schedule = [on](double) { return on; };
  run.Finished = [to](const rp::DrillState& s) { return rp::Norm(s.Proxy - to) < 0.02; };
  run.MeshEveryFrame = realtime;  // scripted: no mesh between the ticks (rpDrillSession.h)
  if (!session.Prepare(options, {}, nullptr, error) || !session.Run(run, result, error)) {
    std::cerr << error << "\n";
    return false;
  }
  const rp::DisplayTimings frames = rp::SplitDisplayFrames(result.Frames);
  const std::vector<double>& contour = frames.ContourMs;
  const std::vector<double>& blocks = frames.Blocks;
  const std::vector<double>& assemble = frames.AssembleMs;
  f.TickP50 = result.TickCompute.P50Us;
  f.TickP99 = result.TickCompute.P99Us;
  f.TickMax = result.TickCompute.MaxUs;
  f.Ticks = result.Ticks;
  f.ContourP95 = rp::NearestRankPercentile(contour, 0.95);
  f.ContourMax = rp::NearestRankPercentile(contour, 1.0);
  f.AssembleP95 = rp::NearestRankPercentile(assemble, 0.95);
  f.Frames = contour.size();
  for (double b : blocks) f.BlocksMean += b / std::max<size_t>(1, blocks.size());
  f.Removed = result.Final.RemovedTotalMm3;
  return true;
}

GridFigures MeasureGrid(double h, const std::vector<rp::Material>& m) {
  GridFigures f;
  f.Grid = h;
  std::string error;
  {
    rp::DrillVolume bone;
    rp::BuildAnalyticBone(LongBone(m), h, m, bone, error);
    f.Blocks = bone.AllocatedBlocks();
    f.MemoryMB = bone.MemoryBytes() / 1e6;
    rp::DrillRunResult result;
    Tunnel(bone, 2.0, f, false, result);
    // The whole (drilled) bone re-contoured from scratch, ours and VTK's, in the same run, each
    // scored against the true surface: the long bone less the burr's capsule (r = 2) from the
    // tunnel's start to where the burr stopped.
    rp::BlockMesher whole(bone);
    f.WholeOursMs = 1e300;
    for (int run = 0; run < WholeBoneRuns; ++run) {
      const auto start = std::chrono::steady_clock::now();
      whole.ContourAll();
      f.WholeOursMs = std::min(f.WholeOursMs, Milliseconds(start));
    }
    f.WholeTriangles = whole.TriangleCount();
    const auto boneSd = LongBone(m).SignedDistance;
    const Vec3 a = TunnelFrom, b = result.Final.Proxy;
    const SignedDistanceFunction drilled = [boneSd, a, b](const Vec3& p) {
      const Vec3 ab = b - a;
      const double t = std::clamp(rp::Dot(p - a, ab) / std::max(rp::Dot(ab, ab), 1e-12), 0.0, 1.0);
      return std::max(boneSd(p), 2.0 - rp::Norm(p - (a + ab * t)));
    };
    f.WholeError = MeasureSurfaceError(whole, drilled);
    f.WholeVTKMs = WholeBoneVTK(bone, f.WholeTrianglesVTK, drilled, &f.WholeErrorVTK);
  }
  {
    // The known answer: a straight stroke inside a homogeneous block.
    rp::DrillVolume block;
    rp::BuildAnalyticBone(rp::BlockBone({-8, -8, -12}, {8, 8, 12}, 1), h, m, block, error);
    rp::SimulatedDevice device;
    const Vec3 from{0.13, -0.07, 6}, to{0.13, -0.07, -4};
    auto path = std::make_shared<rp::WaypointTrajectory>();
    path->Set({0.0, 1e-3, 1e-3 + 10 / 5.0}, {from, from, to}, error);
    device.SetTrajectory(path);
    rp::DrillDisplay display(block);
    rp::DrillSession session(device, block, display);
    rp::DrillSession::Options options;
    options.Servo.RampSeconds = 0;
    options.KeepPath = false;
    const rp::DrillControl on{true, 2.0, 60000};
    session.Prepare(options, {}, nullptr, error);
    session.Servo().PlaceBurr(from, on);
    rp::DrillRunOptions run;
    run.Schedule = [on](double) { return on; };
    run.Finished = [to](const rp::DrillState& s) { return rp::Norm(s.Proxy - to) < 1e-3; };
    run.MaxSeconds = 20;
    rp::DrillRunResult result;
    session.Run(run, result, error);
    f.Expected = M_PI * 4 * 10 + 4.0 / 3.0 * M_PI * 8;
    f.StrokeRemoved = result.Final.RemovedTotalMm3;
    f.ErrorPercent = 100 * (f.StrokeRemoved - f.Expected) / f.Expected;
  }
  std::cerr << "[drill-bench] " << h << " mm: tick p99 " << f.TickP99 << " us, re-contour p95 " << f.ContourP95
            << " ms (whole bone " << f.WholeOursMs << " ms ours, " << f.WholeVTKMs << " ms VTK on "
            << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads; surface error mean " << f.WholeError.MeanMm
            << " / " << f.WholeErrorVTK.MeanMm << " mm, max " << f.WholeError.MaxMm << " / " << f.WholeErrorVTK.MaxMm
            << " mm), volume error " << f.ErrorPercent << " %\n";
  return f;
}

nlohmann::json Json(const GridFigures& f) {
  return {{"gridMm", f.Grid},
          {"tunnel",
           {{"tickP50Us", f.TickP50}, {"tickP99Us", f.TickP99}, {"tickMaxUs", f.TickMax}, {"ticks", f.Ticks},
            {"removedMm3", f.Removed}, {"displayFrames", f.Frames}, {"dirtyBlockRecontourP95Ms", f.ContourP95},
            {"dirtyBlockRecontourMaxMs", f.ContourMax}, {"dirtyBlocksPerFrameMean", f.BlocksMean},
            {"meshAssembleP95Ms", f.AssembleP95}}},
          {"wholeBone",
           {{"storedBlocks", f.Blocks}, {"memoryMB", f.MemoryMB}, {"recontourOursMs", f.WholeOursMs},
            {"recontourVtkFlyingEdgesMs", f.WholeVTKMs}, {"oursOverVtk", f.WholeOursMs / std::max(f.WholeVTKMs, 1e-9)},
            {"threads", vtkSMPTools::GetEstimatedNumberOfThreads()}, {"smpBackend", vtkSMPTools::GetBackend()},
            {"triangles", f.WholeTriangles}, {"trianglesVtk", f.WholeTrianglesVTK},
            {"surfaceErrorMeanMm", f.WholeError.MeanMm}, {"surfaceErrorMaxMm", f.WholeError.MaxMm},
            {"surfaceErrorMeanMmVtk", f.WholeErrorVTK.MeanMm}, {"surfaceErrorMaxMmVtk", f.WholeErrorVTK.MaxMm},
            {"surfaceErrorVertexMeanMm", f.WholeError.VertexMeanMm},
            {"surfaceErrorVertexMeanMmVtk", f.WholeErrorVTK.VertexMeanMm},
            {"distinctVertices", f.WholeError.Vertices}, {"distinctVerticesVtk", f.WholeErrorVTK.Vertices},
            {"surfaceErrorMean", "over the surface: area-weighted mean |distance| of the triangles' corners"}}},
          {"stroke", {{"expectedMm3", f.Expected}, {"removedMm3", f.StrokeRemoved}, {"errorPercent", f.ErrorPercent}}}};
}

// The real knee CT's tibia at 0.3 mm: whole-bone re-contour against a tunnel's dirty blocks.
nlohmann::json RealTibia(const std::vector<rp::Material>& m) {
  const std::string data = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/knee-ct-vhf";
  if (!std::filesystem::exists(data + "/labels.nrrd")) return {{"skipped", "absent: " + data}};
  rp::DrillBoneSource source;
  std::string error;
  vtkNew<vtkImageData> labels;
  vtkNew<vtkMatrix4x4> ijkToRAS;
  rp::VolumeFileData file;
  file.Image = labels;
  file.IJKToRAS = ijkToRAS;
  if (!rp::ReadVolumeFile(data + "/labels.nrrd", file, error) || !rp::ReadVolume(data + "/dicom", source.CT, error))
    return {{"error", error}};
  source.Labels.Image = labels;
  source.Labels.IJKToRAS = ijkToRAS;
  source.BoneLabels = {1};
  source.Spacing = 0.3;
  rp::DrillVolume bone;
  rp::DrillBoneReport report;
  if (!rp::BuildDrillBone(source, m, bone, nullptr, report, error)) return {{"error", error}};
  rp::BlockMesher whole(bone);
  auto start = std::chrono::steady_clock::now();
  whole.ContourAll();
  const double oursMs = Milliseconds(start);
  size_t vtkTriangles = 0;
  const double vtkMs = WholeBoneVTK(bone, vtkTriangles);
  // A tunnel from the anterior surface into the shaft (the CLI test's stroke).
  Vec3 lo, hi;
  bone.BoneBounds(lo, hi);
  const Vec3 centre{0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), hi.z - 60};
  GridFigures f;
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  const Vec3 from{centre.x, hi.y + 3, centre.z}, to = centre;
  path->Set({0.0, rp::Norm(to - from) / 10.0}, {from, to}, error);
  device.SetTrajectory(path);
  rp::DrillDisplay display(bone);
  display.Initialize();
  rp::DrillSession session(device, bone, display);
  rp::DrillSession::Options options;
  options.Servo.RampSeconds = 0;
  options.KeepPath = false;
  session.Prepare(options, {}, nullptr, error);
  rp::DrillRunOptions run;
  const rp::DrillControl on{true, 2.5, 60000};
  run.Schedule = [on](double) { return on; };
  run.Finished = [to](const rp::DrillState& s) { return rp::Norm(s.Proxy - to) < 0.02; };
  run.MaxSeconds = 40;
  run.MeshEveryFrame = false;
  rp::DrillRunResult result;
  session.Run(run, result, error);
  const std::vector<double> contour = rp::SplitDisplayFrames(result.Frames).ContourMs;
  return {{"voxelMm", 0.3},
          {"storedBlocks", report.StoredBlocks},
          {"memoryMB", report.MemoryMB},
          {"buildSeconds", report.Seconds},
          {"corticalMm3", report.VolumeMm3.size() > 0 ? report.VolumeMm3[0] : 0.0},
          {"trabecularMm3", report.VolumeMm3.size() > 1 ? report.VolumeMm3[1] : 0.0},
          {"wholeBoneRecontourOursMs", oursMs},
          {"wholeBoneRecontourVtkFlyingEdgesMs", vtkMs},
          {"wholeBoneTriangles", whole.TriangleCount()},
          {"tunnelTickP99Us", result.TickCompute.P99Us},
          {"tunnelRemovedMm3", result.Final.RemovedTotalMm3},
          {"tunnelDirtyBlockRecontourP95Ms", rp::NearestRankPercentile(contour, 0.95)},
          {"tunnelFrames", contour.size()}};
}

// ---- Google Benchmark cases (per-call timings at 0.3 mm)
struct Fixture {
  std::vector<rp::Material> M = Materials();
  rp::DrillVolume Bone;
  Fixture() {
    std::string error;
    rp::BuildAnalyticBone(LongBone(this->M), 0.3, this->M, this->Bone, error);
  }
};
Fixture& TheFixture() {
  static Fixture* f = new Fixture;
  return *f;
}

void BM_WholeBoneRecontour_BlockMesher(benchmark::State& state) {
  rp::BlockMesher mesher(TheFixture().Bone);
  for (auto _ : state) mesher.ContourAll();
}
BENCHMARK(BM_WholeBoneRecontour_BlockMesher)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_WholeBoneRecontour_VTKFlyingEdges3D(benchmark::State& state) {
  size_t triangles = 0;
  for (auto _ : state) {
    const double ms = WholeBoneVTK(TheFixture().Bone, triangles);
    state.SetIterationTime(ms / 1000);
  }
}
BENCHMARK(BM_WholeBoneRecontour_VTKFlyingEdges3D)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

void BM_OneBlockRecontour(benchmark::State& state) {
  rp::DrillVolume& bone = TheFixture().Bone;
  rp::BlockMesher mesher(bone);
  // A block on the surface (one that has triangles).
  mesher.ContourAll();
  int32_t slot = 0;
  for (size_t s = 0; s < mesher.Blocks().size(); ++s)
    if (mesher.Blocks()[s].TriangleCount() > 50) slot = static_cast<int32_t>(s);
  for (auto _ : state) mesher.Contour(slot);
}
BENCHMARK(BM_OneBlockRecontour)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  const std::string out = rp::bench::OutputDirectory();
  const auto m = Materials();
  nlohmann::json doc;
  std::vector<GridFigures> grids;
  // A quick run (rpBenchmarkConditions.h) checks the figures are written: the coarsest grid only,
  // neither the real-time loop nor the real tibia.
  const bool quick = rp::bench::QuickRun();
  for (double h : quick ? std::vector<double>{Grids[std::size(Grids) - 1]} : std::vector<double>(std::begin(Grids), std::end(Grids))) {
    grids.push_back(MeasureGrid(h, m));
    doc["grids"].push_back(Json(grids.back()));
  }
  // The real 1 kHz loop at 0.3 mm (the target grid), wall-clock compute and period.
  if (!quick) {
    rp::DrillVolume bone;
    std::string error;
    rp::BuildAnalyticBone(LongBone(m), 0.3, m, bone, error);
    GridFigures f;
    rp::DrillRunResult result;
    if (Tunnel(bone, 2.0, f, true, result)) {
      doc["realtime"] = {{"gridMm", 0.3},
                         {"ticks", result.Servo.Ticks},
                         {"computeP50Us", result.Servo.Compute.P50Us},
                         {"computeP99Us", result.Servo.Compute.P99Us},
                         {"computeMaxUs", result.Servo.Compute.MaxUs},
                         {"periodP99Us", result.Servo.Period.P99Us},
                         {"missedDeadlines", result.Servo.MissedDeadlines},
                         {"overruns", result.Servo.Overruns},
                         {"realTimePriority", result.Servo.RealTimePriority},
                         {"dirtyBlockRecontourP95Ms", f.ContourP95},
                         {"removedMm3", result.Final.RemovedTotalMm3}};
    }
  }
  doc["realTibia"] = quick ? nlohmann::json{{"skipped", "quick run"}} : RealTibia(m);

  // ---- CSV and charts
  std::string error;
  std::vector<std::vector<double>> rows;
  for (const GridFigures& f : grids)
    rows.push_back({f.Grid, f.TickP50, f.TickP99, f.ContourP95, f.BlocksMean, f.WholeOursMs, f.WholeVTKMs, f.ErrorPercent,
                    f.MemoryMB});
  rp::bench::WriteCSV(out + "/drilling_grids.csv",
                      {"grid_mm", "tick_p50_us", "tick_p99_us", "dirty_recontour_p95_ms", "dirty_blocks_per_frame",
                       "whole_bone_ours_ms", "whole_bone_vtk_ms", "volume_error_percent", "memory_mb"},
                      rows, error);
  std::vector<rp::bench::Series> tradeoff;
  for (const GridFigures& f : grids) {
    char name[32];
    std::snprintf(name, sizeof name, "%.2f mm grid", f.Grid);
    tradeoff.push_back({name, {f.TickP99}, {std::fabs(f.ErrorPercent)}, true});
  }
  rp::bench::ChartOptions chart{"Time against accuracy: servo tick p99 (tunnel) vs removed-volume error (known stroke)",
                                "servo tick p99 while drilling (us, thread CPU)", "|removed - (pi r^2 L + 4/3 pi r^3)| (%)"};
  rp::bench::WriteChartPNG(out + "/drilling_time_vs_accuracy.png", tradeoff, chart, error);
  std::vector<double> g, tick99, tick50, dirty, whole, wholeVTK, err;
  for (const GridFigures& f : grids) {
    g.push_back(f.Grid);
    tick99.push_back(f.TickP99);
    tick50.push_back(f.TickP50);
    dirty.push_back(f.ContourP95);
    whole.push_back(f.WholeOursMs);
    wholeVTK.push_back(f.WholeVTKMs);
    err.push_back(std::fabs(f.ErrorPercent));
  }
  rp::bench::WriteChartPNG(out + "/drilling_recontour.png",
                           {{"dirty blocks per 30 Hz frame, p95", g, dirty},
                            {"whole bone, our block mesher", g, whole},
                            {"whole bone, vtkFlyingEdges3D (the VTK way)", g, wholeVTK}},
                           {"Re-contour per display frame: dirty blocks vs the whole bone (Ø40 x 120 mm long bone)",
                            "voxel size (mm)", "time (ms)", false, true},
                           error);
  rp::bench::WriteChartPNG(out + "/drilling_tick.png",
                           {{"p50", g, tick50}, {"p99", g, tick99}, {"target (0.3 mm)", {0.2, 0.5}, {100, 100}}},
                           {"Servo tick while drilling a tunnel (thread CPU)", "voxel size (mm)", "time per tick (us)"},
                           error);
  rp::bench::WriteChartPNG(out + "/drilling_volume_error.png", {{"|error| of the stroke volume", g, err}},
                           {"Removed volume against the analytic stroke (r = 2, L = 10 mm)", "voxel size (mm)", "error (%)"},
                           error);
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpDrillingBenchmark");  // the load after, the steal over the run
  rp::bench::WriteFiguresJSON(out + "/drilling_benchmark.json", doc, error);
  std::cout << doc.dump(2) << "\n";
  benchmark::Shutdown();
  return 0;
}
