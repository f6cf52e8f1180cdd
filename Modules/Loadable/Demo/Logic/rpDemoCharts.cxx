// Demo stage: speed against accuracy of each module, measured in this run on this patient's
// data beside the VTK way a user would otherwise take (the full benchmarks, on the 512×512×300
// phantom, are in Testing/Benchmarks; see the README). Charts go into the report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>
#include <vtkGenericCell.h>
#include <vtkImageData.h>
#include <vtkLandmarkTransform.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>

#include "rpBVH.h"
#include "rpBenchmarkChart.h"
#include "rpDemoStages.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpImageVolume.h"
#include "rpKneePhantom.h"
#include "rpLabelmapToMesh.h"
#include "rpPairedPointRegistration.h"
#include "rpRegistrationAccuracy.h"
#include "rpReport.h"
#include "rpStageRunner.h"
#include "rpSurfaceError.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }


// Femur mesh: time against mean distance to the true femur surface, ours (smoothing × contour
// grid) and Slicer's default pipeline (discrete flying edges → windowed sinc → normals), all
// meshing the phantom's true femur labels, so the chart measures the meshing and not the
// segmentation. One series per contour grid, each drawing the points its legend names.
void MeshSpeedAccuracy(DemoState& state, const std::string& stage) {
  if (!state.CT || !state.HasGroundTruth()) {
    state.Report->AddNotScored(stage, "mesh time against surface error", "needs the phantom's true femur");
    return;
  }
  const KneeBone& femur = KneeBones()[0];
  const ImageVolume& labels = state.Phantom->Labels;
  vtkNew<vtkImageData> mask;
  mask->DeepCopy(labels.Image);
  auto* v = static_cast<unsigned char*>(mask->GetScalarPointer());
  for (vtkIdType n = 0; n < mask->GetNumberOfPoints(); ++n) v[n] = v[n] == femur.Cortical || v[n] == femur.Trabecular;
  double bounds[6];
  state.CT->GetRASBounds(bounds);
  for (int a = 0; a < 3; ++a) bounds[2 * a] += 3.0, bounds[2 * a + 1] -= 3.0;  // not the cut at the field's edge
  const auto model = state.Phantom->Model;
  const auto truth = model->SurfacePoints(femur.Surface, 3000, bounds);
  auto sdf = [model, &femur](const double p[3]) { return model->SignedDistance(femur.Surface, p); };
  struct Config {
    MeshMethod Method;
    double Sigma, Step;
    bench::Series* Into;
  };
  bench::Series grid1{"ours, contour grid 1 voxel (sigma 1 and 1.5)", {}, {}, false},
      grid2{"ours, contour grid 2 voxels (sigma 1 and 1.5)", {}, {}, false}, slicer{"Slicer default pipeline", {}, {}, true};
  const std::vector<Config> configs = {{MeshMethod::Gaussian, 1.0, 1.0, &grid1},
                                       {MeshMethod::Gaussian, 1.5, 1.0, &grid1},
                                       {MeshMethod::Gaussian, 1.0, 2.0, &grid2},
                                       {MeshMethod::Gaussian, 1.5, 2.0, &grid2},
                                       {MeshMethod::SlicerDefault, 1.0, 1.0, &slicer}};
  double slicerTime = 0, slicerError = 0, bestRatio = 0, bestError = 0;
  std::vector<std::pair<double, double>> ours;
  for (const Config& c : configs) {
    MeshOptions options;
    options.Method = c.Method;
    options.Sigma = c.Sigma;
    for (double& s : options.GridStep) s = c.Step;
    vtkNew<vtkPolyData> mesh;
    MeshStats stats;
    std::string error;
    const auto start = Clock::now();
    if (!LabelmapToMesh(mask, labels.IJKToRAS, 1, options, mesh, stats, error)) {
      throw std::runtime_error("meshing the femur: " + error);
    }
    const double t = Seconds(start);
    const double e = CompareToSurface(mesh, sdf, truth, bounds).MeanMm;
    c.Into->X.push_back(t * 1000);
    c.Into->Y.push_back(e);
    if (c.Method == MeshMethod::SlicerDefault) {
      slicerTime = t;
      slicerError = e;
    } else {
      ours.emplace_back(t, e);
    }
  }
  for (const auto& [t, e] : ours)
    if (e <= slicerError && slicerTime / t > bestRatio) bestRatio = slicerTime / t, bestError = e;
  state.Report->AddFigure(stage, "femur mesh: Slicer default pipeline", slicerTime * 1000, "ms",
                          "mean distance to the true femur " + std::to_string(slicerError).substr(0, 5) + " mm");
  if (bestRatio > 0) {
    state.Report->AddFigureAbove(stage, "femur mesh: speed-up at equal or lower error than Slicer's default", bestRatio, "×",
                                 1.5, "mean distance " + std::to_string(bestError).substr(0, 5) + " mm");
  } else {
    state.Report->AddNotScored(stage, "femur mesh: speed-up at equal or lower error",
                               "no configuration of ours matched the default's error on this volume");
  }
  std::string error;
  if (CanDrawPicturesOrWarn(state, stage, "speed-accuracy-mesh.png"))
    state.Report->AddPictureIf(
        bench::WriteChartPNG((fs::path(state.Output) / "speed-accuracy-mesh.png").string(), {grid1, grid2, slicer},
                             {"Femur (true labels): meshing time against mean surface error", "time (ms)",
                              "mean distance to the true femur surface (mm)"},
                             error),
        stage, "speed-accuracy-mesh.png",
        "SegmentationToMesh: time against accuracy meshing the phantom's true femur labels, ours "
        "across smoothing (sigma) and contour grid against Slicer's default pipeline in the same run; "
        "distances to the real femur surface inside the CT.",
        error);
}

// Paired-point solve time (ours vs vtkLandmarkTransform) and TRE against the number of fiducials.
void RegistrationSpeedAccuracy(DemoState& state, const std::string& stage) {
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss(0.0, 1.0);
  bench::Series oursTime{"ours (Horn)", {}, {}, false}, vtkTime{"vtkLandmarkTransform", {}, {}, false};
  bench::Series treSeries{"RMS TRE at 80 mm, FLE 0.5 mm", {}, {}, false}, predicted{"predicted (Fitzpatrick)", {}, {}, false};
  const Eigen::Vector3d target(0, 0, 80);
  for (int n : {4, 6, 8, 12, 20, 40}) {
    PointList from(static_cast<size_t>(n)), to(static_cast<size_t>(n));
    for (auto& p : from) p = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)) * 50.0;
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    for (size_t i = 0; i < from.size(); ++i) to[i] = r * from[i] + Eigen::Vector3d(10, -20, 30);
    const int repeats = 2000;
    SimilarityTransform solved;
    auto start = Clock::now();
    for (int k = 0; k < repeats; ++k) SolvePairedPoints(from.data(), to.data(), nullptr, from.size(), RegistrationMode::Rigid, solved);
    oursTime.X.push_back(n);
    oursTime.Y.push_back(Seconds(start) / repeats * 1e6);
    vtkNew<vtkPoints> a, b;
    a->SetDataTypeToDouble();
    b->SetDataTypeToDouble();
    for (size_t i = 0; i < from.size(); ++i) a->InsertNextPoint(from[i].data()), b->InsertNextPoint(to[i].data());
    vtkNew<vtkLandmarkTransform> landmark;
    landmark->SetModeToRigidBody();
    landmark->SetSourceLandmarks(a);
    landmark->SetTargetLandmarks(b);
    start = Clock::now();
    for (int k = 0; k < repeats; ++k) {
      landmark->Modified();
      landmark->Update();
    }
    vtkTime.X.push_back(n);
    vtkTime.Y.push_back(Seconds(start) / repeats * 1e6);
    // Monte Carlo TRE with isotropic FLE 0.5 mm against the prediction.
    double sum2 = 0;
    const int trials = 400;
    for (int k = 0; k < trials; ++k) {
      PointList noisy = from;
      for (auto& p : noisy) p += Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)) * (0.5 / std::sqrt(3.0));
      SolvePairedPoints(noisy.data(), to.data(), nullptr, noisy.size(), RegistrationMode::Rigid, solved);
      sum2 += (solved.Apply(target) - (r * target + Eigen::Vector3d(10, -20, 30))).squaredNorm();
    }
    treSeries.X.push_back(n);
    treSeries.Y.push_back(std::sqrt(sum2 / trials));
    predicted.X.push_back(n);
    predicted.Y.push_back(TREPredictor(to, 0.5).PredictRMS(r * target + Eigen::Vector3d(10, -20, 30)));
  }
  const double speedup = vtkTime.Y.front() / oursTime.Y.front();
  state.Report->AddFigureAbove(stage, "paired-point solve, 4 pairs: speed-up over vtkLandmarkTransform", speedup, "×", 10.0,
                               std::to_string(oursTime.Y.front()).substr(0, 5) + " µs vs " +
                                   std::to_string(vtkTime.Y.front()).substr(0, 5) + " µs");
  state.Report->AddFigureBelow(stage, "measured/predicted TRE − 1 at N = 6 (400 trials)",
                               std::abs(treSeries.Y[1] / predicted.Y[1] - 1.0), "", 0.15);
  std::string error;
  if (!CanDrawPicturesOrWarn(state, stage, "registration speed-accuracy charts")) return;
  state.Report->AddPictureIf(
      bench::WriteChartPNG((fs::path(state.Output) / "speed-accuracy-registration-time.png").string(), {oursTime, vtkTime},
                           {"Paired-point registration: time per solve", "fiducial pairs", "time (µs)"}, error),
      stage, "speed-accuracy-registration-time.png",
      "LandmarkRegistration: time per rigid solve against vtkLandmarkTransform in the same run.", error);
  state.Report->AddPictureIf(
      bench::WriteChartPNG((fs::path(state.Output) / "speed-accuracy-registration-tre.png").string(), {treSeries, predicted},
                           {"TRE at a target 80 mm from the centroid", "fiducial pairs", "RMS TRE (mm)"}, error),
      stage, "speed-accuracy-registration-tre.png",
      "LandmarkRegistration: measured RMS TRE (Monte Carlo, FLE 0.5 mm) and its prediction.", error);
}

// Closest-point query on this patient's haptic bone mesh: our BVH vs vtkStaticCellLocator.
void HapticQuerySpeed(DemoState& state, const std::string& stage) {
  vtkPolyData* mesh = nullptr;
  for (const auto& id : state.HapticModelIDs) {
    auto* model = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id));
    if (model && model->GetTissueClass() == "bone" && (!mesh || model->GetPolyData()->GetNumberOfCells() > mesh->GetNumberOfCells())) {
      mesh = model->GetPolyData();
    }
  }
  if (!mesh) return;
  TriangleMesh triangles;
  std::string error;
  if (!PolyDataToTriangleMesh(mesh, nullptr, triangles, error)) throw std::runtime_error(error);
  BVH tree;
  tree.Build(triangles);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(mesh);
  locator->BuildLocator();
  double b[6];
  mesh->GetBounds(b);
  std::mt19937 rng(5);
  std::vector<Vec3> queries(4000);
  for (auto& q : queries) {
    q = {std::uniform_real_distribution<double>(b[0] - 5, b[1] + 5)(rng), std::uniform_real_distribution<double>(b[2] - 5, b[3] + 5)(rng),
         std::uniform_real_distribution<double>(b[4] - 5, b[5] + 5)(rng)};
  }
  double worst = 0;
  auto start = Clock::now();
  std::vector<double> ours(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    ClosestPointHit hit;
    tree.ClosestPoint(queries[i], 1e9, hit);
    ours[i] = Norm(hit.Point - queries[i]);
  }
  const double oursUs = Seconds(start) / queries.size() * 1e6;
  vtkNew<vtkGenericCell> cell;
  start = Clock::now();
  for (size_t i = 0; i < queries.size(); ++i) {
    double x[3] = {queries[i].x, queries[i].y, queries[i].z}, closest[3], d2;
    vtkIdType cellId;
    int subId;
    locator->FindClosestPoint(x, closest, cell, cellId, subId, d2);
    worst = std::max(worst, std::abs(std::sqrt(d2) - ours[i]));
  }
  const double vtkUs = Seconds(start) / queries.size() * 1e6;
  state.Report->AddFigureAbove(stage, "closest point on the bone haptic mesh: speed-up over vtkStaticCellLocator", vtkUs / oursUs, "×",
                               1.0, std::to_string(oursUs).substr(0, 5) + " µs vs " + std::to_string(vtkUs).substr(0, 5) +
                                        " µs per query, " + std::to_string(mesh->GetNumberOfCells()) + " triangles");
  state.Report->AddFigureBelow(stage, "closest point: largest distance difference to VTK's answer", worst, "mm", 1e-6);
}

}  // namespace

void MeasureSpeedAgainstAccuracy(DemoState& state) {
  const std::string stage = "Speed against accuracy";
  state.Runner->Progress(0.1, "meshing the femur five ways");
  MeshSpeedAccuracy(state, stage);
  state.Runner->Progress(0.6, "paired-point registration");
  RegistrationSpeedAccuracy(state, stage);
  state.Runner->Progress(0.9, "closest-point queries");
  HapticQuerySpeed(state, stage);
  state.Report->AddNote("Full benchmarks (512×512×300 phantom, 1M-triangle meshes, 60 s servo runs, OpenIGTLink "
                        "ingestion): build/bin/rp*Benchmark, see the README.");
}

}  // namespace rp
