// Whole-process speed of `roboplan mesh` on a 512 x 512 x 300 two-label labelmap (gzip NRRD,
// 0.7 x 0.7 x 1 mm, an ellipsoid and a torus), against Slicer's default pipeline on the same data
// in the same run:
//   slicer_compute   the labelmap already in memory, per label vtkDiscreteFlyingEdges3D → windowed
//                    sinc (20 iterations, pass band 0.01, normalized coordinates) → vtkPolyDataNormals
//                    (the baseline: compute only, no reading or writing);
//   vtk_itk_script   what a user's script does: ITK reads the .nrrd.gz, the same VTK pipeline, one
//                    .vtp per label (vtkXMLPolyDataWriter);
//   roboplan_mesh    `roboplan mesh labels.nrrd --out DIR` as a child process (start to exit):
//                    default (display + haptic meshes) and --no-haptic;
//   read_nrrd_gz     reading the file alone (rp::ReadVolumeFile: libdeflate), to show what dominates,
//                    beside read_nrrd_gz_itk, ITK's ImageFileReader + NrrdImageIO (zlib) on the same file.
// And the CT case on a synthetic abdomen (512 x 512 x 134, 0.78 x 0.78 x 2.5 mm, short
// gzip NRRD: a body of fat and soft tissue with noise, spine, ribs, iliac wings, and the CT table
// under it, dense enough to pass the bone threshold as real tables often do):
//   abdomen_bone     `roboplan mesh abdomen.nrrd --preset bone` as a process (target < 5 s on 2
//                    cores); fails unless every haptic mesh is within its budget and watertight.
// And start-up: `roboplan <command> --help` for every command `roboplan --help` lists (and
// `roboplan --help`), 10 runs each, start to exit (target <= 30 ms before a command's work begins).
// Writes whole_process.{csv,json}, whole_process_seconds.png (bars), startup.{csv,json} and
// startup_ms.png to $ROBOPLAN_BENCHMARK_OUTPUT.
//
//   ./bin/rpMeshWholeProcessBenchmark
//   ./bin/rpMeshWholeProcessBenchmark --startup-chart <run>/startup.json startup_ms.png   (redraw only)
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkNrrdImageIO.h>
#include <nlohmann/json.hpp>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkWindowedSincPolyDataFilter.h>
#include <vtkXMLPolyDataWriter.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpVolumeIO.h"

extern char** environ;

namespace fs = std::filesystem;

namespace {

constexpr int Dims[3] = {512, 512, 300};
constexpr double Spacing[3] = {0.7, 0.7, 1.0};

fs::path WorkDir() { return fs::path(rp::bench::OutputDirectory()) / "whole_process_work"; }
// Named as Slicer names labelmap volumes ("-label"), so `roboplan mesh` takes it as a labelmap.
fs::path LabelmapPath() { return WorkDir() / "two-label.nrrd"; }

// Writes `image` (gzip NRRD) with its centre at the RAS origin; exits on failure.
void WriteCentredVolume(const fs::path& path, vtkImageData* image, const double spacing[3]) {
  int dims[3];
  image->GetDimensions(dims);
  vtkNew<vtkMatrix4x4> ijkToRAS;
  for (int a = 0; a < 3; ++a) {
    ijkToRAS->SetElement(a, a, spacing[a]);
    ijkToRAS->SetElement(a, 3, -dims[a] / 2.0 * spacing[a]);
  }
  std::string error;
  if (!rp::WriteVolumeFile(path.string(), image, ijkToRAS, {}, error, true)) {
    std::fprintf(stderr, "writing %s: %s\n", path.c_str(), error.c_str());
    std::exit(1);
  }
}

// Label 1: an ellipsoid (radii 70, 55, 120 mm); label 2: a torus (R 45, r 14 mm) beside it.
void WriteLabelmap() {
  vtkNew<vtkImageData> image;
  image->SetDimensions(Dims[0], Dims[1], Dims[2]);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(image->GetScalarPointer());
  const double c1[3] = {-55, 0, 0}, c2[3] = {85, 10, 20};
  for (int k = 0; k < Dims[2]; ++k)
    for (int j = 0; j < Dims[1]; ++j)
      for (int i = 0; i < Dims[0]; ++i) {
        const double x = (i - Dims[0] / 2.0) * Spacing[0], y = (j - Dims[1] / 2.0) * Spacing[1],
                     z = (k - Dims[2] / 2.0) * Spacing[2];
        const double e = std::pow((x - c1[0]) / 70, 2) + std::pow((y - c1[1]) / 55, 2) + std::pow((z - c1[2]) / 120, 2);
        const double ring = std::hypot(x - c2[0], y - c2[1]) - 45;
        const double t = ring * ring + (z - c2[2]) * (z - c2[2]);
        *v++ = e < 1 ? 1 : (t < 14 * 14 ? 2 : 0);
      }
  WriteCentredVolume(LabelmapPath(), image, Spacing);
}

fs::path AbdomenPath() { return WorkDir() / "abdomen.nrrd"; }

// Hounsfield units of the synthetic abdomen at (x, y, z) mm (x left-right, y posterior-anterior).
short AbdomenHU(double x, double y, double z) {
  auto ellipse = [](double u, double v, double a, double b) { return (u / a) * (u / a) + (v / b) * (v / b); };
  // The CT table: an 8 mm carbon-fibre slab under the patient, 280 HU.
  if (y > -121 && y < -113 && std::abs(x) < 230) return 280;
  const double body = ellipse(x, y - 10, 165, 115);
  if (body > 1) return -1000;
  // Spine: vertebral bodies (25 mm, discs of 8 mm between them), cortical shell over cancellous
  // bone, and a spinous process behind each.
  const double vz = std::fmod(z + 1000, 33.0);
  const double r = std::hypot(x, y + 55);
  if (vz < 25 && r < 21) return r > 19.5 ? 750 : 260;
  if (vz < 25 && std::abs(x) < 6 && y < -76 && y > -100) return 500;
  // Ribs: a 6 mm tube along an inner ellipse every 36 mm up to mid-height, from the spine round to
  // the front (not across it).
  const double rz = std::fmod(z + 1000, 36.0) - 18;
  if (z > -10 && std::abs(rz) < 6 && y > -70 && std::abs(x) > 12) {
    const double t = std::atan2((y - 5) / 95, x / 140);
    const double ex = 140 * std::cos(t), ey = 5 + 95 * std::sin(t);
    const double d = std::hypot(std::hypot(x - ex, y - ey), rz);
    if (d < 6 && (ey < 70)) return d > 4.5 ? 650 : 300;
  }
  // Iliac wings low in the volume: thick tilted plates either side.
  if (z < -90)
    for (double side : {-1.0, 1.0})
      if (ellipse(x - side * 95, y + 25 + 0.3 * side * (x - side * 95), 55, 14) + std::pow((z + 140) / 60, 2) < 1)
        return 420;
  return body > std::pow(150.0 / 165, 2) ? -100 : 40;  // subcutaneous fat, then soft tissue
}

void WriteAbdomen() {
  constexpr int dims[3] = {512, 512, 134};
  constexpr double spacing[3] = {0.78, 0.78, 2.5};
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < dims[2]; ++k) {
    std::mt19937 random(static_cast<unsigned>(k));  // the same noise in every run
    std::normal_distribution<double> noise(0, 18);
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const double x = (i - dims[0] / 2.0) * spacing[0], y = (j - dims[1] / 2.0) * spacing[1],
                     z = (k - dims[2] / 2.0) * spacing[2];
        const short hu = AbdomenHU(x, y, z);
        *v++ = hu == -1000 ? hu : static_cast<short>(std::lround(hu + noise(random)));
      }
  }
  WriteCentredVolume(AbdomenPath(), image, spacing);
}

// The labelmap in memory for the compute-only baseline (read once, outside the timing).
vtkImageData* InMemoryLabelmap() {
  static vtkNew<vtkImageData> image;
  static bool loaded = [] {
    vtkNew<vtkMatrix4x4> ijkToRAS;
    rp::VolumeFileData data;
    data.Image = image;
    data.IJKToRAS = ijkToRAS;
    std::string error;
    if (!rp::ReadVolumeFile(LabelmapPath().string(), data, error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      std::exit(1);
    }
    return true;
  }();
  (void)loaded;
  return image;
}

// Slicer's closed-surface conversion of one label (vtkBinaryLabelmapToClosedSurfaceConversionRule
// with its defaults: smoothing factor 0.5 → pass band 0.01, 20 iterations, normals on).
vtkSmartPointer<vtkPolyData> SlicerPipeline(vtkImageData* image, int label) {
  vtkNew<vtkDiscreteFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, label);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  vtkNew<vtkWindowedSincPolyDataFilter> smoother;
  smoother->SetInputConnection(contour->GetOutputPort());
  smoother->SetNumberOfIterations(20);
  smoother->SetPassBand(0.01);
  smoother->BoundarySmoothingOff();
  smoother->FeatureEdgeSmoothingOff();
  smoother->NonManifoldSmoothingOn();
  smoother->NormalizeCoordinatesOn();
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(smoother->GetOutputPort());
  normals->ConsistencyOn();
  normals->SplittingOff();
  normals->Update();
  return normals->GetOutput();
}

std::map<std::string, double> fastest;  // config → fastest seconds over the repetitions
std::map<std::string, double> triangles;

void Keep(const std::string& name, double seconds) {
  auto it = fastest.find(name);
  if (it == fastest.end() || seconds < it->second) fastest[name] = seconds;
}

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void BM_SlicerCompute(benchmark::State& state) {
  vtkImageData* image = InMemoryLabelmap();
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    long n = 0;
    for (int label : {1, 2}) n += SlicerPipeline(image, label)->GetNumberOfPolys();
    Keep("slicer_compute", Since(t0));
    triangles["slicer_compute"] = static_cast<double>(n);
  }
}

void BM_VtkItkScript(benchmark::State& state) {
  const fs::path out = WorkDir() / "vtk_itk";
  fs::create_directories(out);
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    using Image = itk::Image<unsigned char, 3>;
    auto reader = itk::ImageFileReader<Image>::New();
    reader->SetImageIO(itk::NrrdImageIO::New());
    reader->SetFileName(LabelmapPath().string());
    reader->Update();
    Image* itkImage = reader->GetOutput();
    const auto size = itkImage->GetLargestPossibleRegion().GetSize();
    vtkNew<vtkImageData> image;
    image->SetDimensions(static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2]));
    image->SetSpacing(itkImage->GetSpacing()[0], itkImage->GetSpacing()[1], itkImage->GetSpacing()[2]);
    image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    std::memcpy(image->GetScalarPointer(), itkImage->GetBufferPointer(), size[0] * size[1] * size[2]);
    for (int label : {1, 2}) {
      vtkNew<vtkXMLPolyDataWriter> writer;
      writer->SetInputData(SlicerPipeline(image, label));
      writer->SetFileName((out / ("label" + std::to_string(label) + ".vtp")).string().c_str());
      writer->Write();
    }
    Keep("vtk_itk_script", Since(t0));
  }
}

fs::path RoboplanExe() { return fs::read_symlink("/proc/self/exe").parent_path() / "roboplan"; }

// Runs `args` (args[0] the program) with stdout to `stdoutPath` and stderr to /dev/null; true when
// it exited with 0.
bool RunChild(const std::vector<std::string>& args, const std::string& stdoutPath) {
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, stdoutPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  int status = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Runs `roboplan mesh <input>` (stdout to a JSON file) and returns its wall time; the process'
// own figure (from after argument parsing to the end) goes to `inside`. Fails the benchmark
// unless every haptic mesh is within its budget and watertight.
double RunRoboplan(const fs::path& input, const std::vector<std::string>& extra, const std::string& name,
                   double& inside, benchmark::State& state) {
  const fs::path exe = RoboplanExe();
  const fs::path out = WorkDir() / name;
  fs::remove_all(out);
  std::vector<std::string> args = {exe.string(), "mesh", input.string(), "--out", out.string(), "--json"};
  args.insert(args.end(), extra.begin(), extra.end());
  const std::string jsonPath = (WorkDir() / (name + ".json")).string();
  const auto t0 = std::chrono::steady_clock::now();
  if (!RunChild(args, jsonPath)) {
    state.SkipWithError(("roboplan mesh failed (" + exe.string() + ")").c_str());
    return 0;
  }
  const double seconds = Since(t0);
  std::ifstream in(jsonPath);
  const auto doc = nlohmann::json::parse(in, nullptr, false);
  inside = doc.is_object() ? doc.value("seconds", 0.0) : 0.0;
  long n = 0;
  if (doc.is_object())
    for (const auto& s : doc["segments"]) {
      n += s.contains("display") ? s["display"].value("triangles", 0L) : 0L;
      if (s.contains("haptic") && !(s["haptic"].value("withinBudget", false) && s["haptic"].value("watertight", false))) {
        state.SkipWithError((name + ": haptic mesh of " + s.value("id", std::string()) +
                             " over its budget or not watertight").c_str());
        return 0;
      }
    }
  triangles[name] = static_cast<double>(n);
  return seconds;
}

void BM_RoboplanMesh(benchmark::State& state, fs::path input, std::vector<std::string> extra, std::string name) {
  for (auto _ : state) {
    double inside = 0;
    const double seconds = RunRoboplan(input, extra, name, inside, state);
    if (seconds <= 0) return;
    Keep(name, seconds);
    Keep(name + "_inside", inside);
  }
}

void BM_ReadNrrdGz(benchmark::State& state) {
  for (auto _ : state) {
    vtkNew<vtkImageData> image;
    vtkNew<vtkMatrix4x4> ijkToRAS;
    rp::VolumeFileData data;
    data.Image = image;
    data.IJKToRAS = ijkToRAS;
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    if (!rp::ReadVolumeFile(LabelmapPath().string(), data, error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    Keep("read_nrrd_gz", Since(t0));
  }
}

void BM_ReadNrrdGzITK(benchmark::State& state) {
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    auto reader = itk::ImageFileReader<itk::Image<unsigned char, 3>>::New();
    reader->SetImageIO(itk::NrrdImageIO::New());
    reader->SetFileName(LabelmapPath().string());
    reader->Update();
    Keep("read_nrrd_gz_itk", Since(t0));
  }
}

// Start-up: `roboplan <command> --help` for every command `roboplan --help` lists, and `roboplan
// --help` itself, start to exit: the process, its libraries and the command's module loaded and
// the arguments parsed, before any work begins (target <= 30 ms).
constexpr double StartupTargetMs = 30;
std::map<std::string, std::vector<double>> startupSeconds;  // command -> every run's seconds

std::vector<std::string> ListedCommands() {
  const std::string listing = (WorkDir() / "commands.txt").string();
  std::vector<std::string> commands;
  if (!RunChild({RoboplanExe().string(), "--help"}, listing)) return commands;
  std::ifstream in(listing);
  bool inList = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("commands:", 0) == 0) inList = true;
    else if (inList && line.empty()) break;
    else if (inList && line.rfind("  ", 0) == 0) commands.push_back(line.substr(2, line.find(' ', 2) - 2));
  }
  return commands;
}

void BM_Startup(benchmark::State& state, std::string command) {
  std::vector<std::string> args = {RoboplanExe().string()};
  if (command != "--help") args.push_back(command);
  args.push_back("--help");
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!RunChild(args, "/dev/null")) {
      state.SkipWithError(("roboplan " + command + " --help failed").c_str());
      return;
    }
    startupSeconds[command].push_back(Since(t0));
  }
}

// startup_ms.png from startup.json's commands: p50 and slowest per command, one row each (the
// command names are long: horizontal bars, the names down the left).
bool DrawStartupChart(const nlohmann::json& doc, const std::string& path, std::string& error) {
  std::vector<std::string> categories;
  rp::bench::Series p50{"p50 (ms)", {}, {}}, slowest{"slowest (ms)", {}, {}};
  for (const auto& command : doc.value("commands", nlohmann::json::array())) {
    categories.push_back(command.value("command", std::string("?")));
    p50.Y.push_back(command.value("p50Ms", 0.0));
    slowest.Y.push_back(command.value("slowestMs", 0.0));
  }
  rp::bench::ChartOptions chart;
  chart.Title = "Start-up: roboplan <command> --help, start to exit (target <= " +
                std::to_string(static_cast<int>(doc.value("targetMs", StartupTargetMs))) + " ms)";
  chart.YLabel = "ms";
  chart.HorizontalBars = true;
  chart.Width = 1000;
  chart.Height = 140 + 34 * static_cast<int>(categories.size());
  return rp::bench::WriteBarChartPNG(path, categories, {p50, slowest}, chart, error);
}

// startup.{csv,json} and startup_ms.png: p50, fastest and slowest of each command's runs.
void ReportStartup(const std::string& out) {
  nlohmann::json doc = {{"targetMs", StartupTargetMs}, {"commands", nlohmann::json::array()}};
  std::vector<std::vector<double>> rows;
  double worst = 0;
  std::printf("\nstart-up, `roboplan <command> --help` start to exit (target <= %.0f ms):\n", StartupTargetMs);
  for (auto& [command, runs] : startupSeconds) {
    std::sort(runs.begin(), runs.end());
    const double median = 1e3 * runs[runs.size() / 2], low = 1e3 * runs.front(), high = 1e3 * runs.back();
    worst = std::max(worst, median);
    std::printf("  %-22s p50 %6.1f ms  fastest %6.1f  slowest %6.1f  (%zu runs)\n", command.c_str(), median, low, high,
                runs.size());
    doc["commands"].push_back({{"command", command}, {"p50Ms", median}, {"fastestMs", low}, {"slowestMs", high},
                               {"runs", runs.size()}, {"withinTarget", median <= StartupTargetMs}});
    rows.push_back({double(rows.size()), median, low, high});
  }
  doc["worstP50Ms"] = worst;
  doc["allWithinTarget"] = !startupSeconds.empty() && worst <= StartupTargetMs;
  std::string error;
  rp::bench::WriteCSV(out + "/startup.csv", {"command_index", "p50_ms", "fastest_ms", "slowest_ms"}, rows, error);
  rp::bench::WriteFiguresJSON(out + "/startup.json", doc, error);
  DrawStartupChart(doc, out + "/startup_ms.png", error);  // names what it wrote
}

// `--startup-chart <startup.json> <png>`: that chart again from a run's figures, nothing measured.
int RedrawStartupChart(const std::string& figures, const std::string& png) {
  std::ifstream in(figures);
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
  std::string error;
  if (doc.is_discarded() || !doc.contains("commands")) {
    std::fprintf(stderr, "rpMeshWholeProcessBenchmark: %s holds no start-up figures (startup.json)\n", figures.c_str());
    return 2;
  }
  if (!DrawStartupChart(doc, png, error)) {
    std::fprintf(stderr, "rpMeshWholeProcessBenchmark: %s\n", error.c_str());
    return 1;
  }
  std::printf("wrote %s\n", png.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--startup-chart") == 0) return RedrawStartupChart(argv[2], argv[3]);
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  fs::create_directories(WorkDir());
  const auto t0 = std::chrono::steady_clock::now();
  WriteLabelmap();
  std::printf("labelmap %dx%dx%d written (%s, %.1f MB) in %.1f s\n", Dims[0], Dims[1], Dims[2],
              LabelmapPath().c_str(), fs::file_size(LabelmapPath()) / 1e6, Since(t0));
  WriteAbdomen();
  std::printf("abdomen 512x512x134 written (%s, %.1f MB)\n", AbdomenPath().c_str(), fs::file_size(AbdomenPath()) / 1e6);
  auto reg = [](benchmark::internal::Benchmark* b) {
    b->Iterations(1)->Repetitions(3)->Unit(benchmark::kMillisecond)->UseRealTime();
  };
  reg(benchmark::RegisterBenchmark("BM_SlicerCompute", BM_SlicerCompute));
  reg(benchmark::RegisterBenchmark("BM_VtkItkScript", BM_VtkItkScript));
  reg(benchmark::RegisterBenchmark("BM_RoboplanMesh/default", BM_RoboplanMesh, LabelmapPath(),
                                   std::vector<std::string>{}, std::string("roboplan_mesh")));
  reg(benchmark::RegisterBenchmark("BM_RoboplanMesh/no_haptic", BM_RoboplanMesh, LabelmapPath(),
                                   std::vector<std::string>{"--no-haptic"}, std::string("roboplan_mesh_no_haptic")));
  reg(benchmark::RegisterBenchmark("BM_RoboplanMesh/abdomen_bone", BM_RoboplanMesh, AbdomenPath(),
                                   std::vector<std::string>{"--preset", "bone"}, std::string("abdomen_bone")));
  reg(benchmark::RegisterBenchmark("BM_ReadNrrdGz", BM_ReadNrrdGz));
  reg(benchmark::RegisterBenchmark("BM_ReadNrrdGzITK", BM_ReadNrrdGzITK));
  for (const std::string& command : ListedCommands())
    benchmark::RegisterBenchmark(("BM_Startup/" + command).c_str(), BM_Startup, command)
        ->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("BM_Startup/--help", BM_Startup, std::string("--help"))
      ->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RunSpecifiedBenchmarks();

  const double baseline = fastest.count("slicer_compute") ? fastest["slicer_compute"] : 0;
  const std::vector<std::pair<std::string, std::string>> order = {
      {"slicer_compute", "Slicer default, compute only (baseline)"},
      {"vtk_itk_script", "ITK read + Slicer pipeline + VTK write"},
      {"roboplan_mesh", "roboplan mesh (process)"},
      {"roboplan_mesh_inside", "  of which after start-up"},
      {"roboplan_mesh_no_haptic", "roboplan mesh --no-haptic (process)"},
      {"read_nrrd_gz", "reading the .nrrd (gzip) alone"},
      {"read_nrrd_gz_itk", "  the same with ITK's NrrdImageIO"}};
  nlohmann::json doc = nlohmann::json::array();
  std::vector<std::vector<double>> rows;
  std::vector<std::string> categories;
  rp::bench::Series bars;
  bars.Name = "seconds (fastest of 3)";
  for (size_t i = 0; i < order.size(); ++i) {
    const auto& [key, label] = order[i];
    if (!fastest.count(key)) continue;
    const double s = fastest[key];
    const double ratio = baseline > 0 ? s / baseline : 0;
    std::printf("%-45s %7.3f s  %5.2fx baseline%s\n", label.c_str(), s, ratio,
                triangles.count(key) ? ("  " + std::to_string(static_cast<long>(triangles[key])) + " triangles").c_str()
                                     : "");
    doc.push_back({{"config", key}, {"label", label}, {"seconds", s}, {"timesBaseline", ratio},
                   {"triangles", triangles.count(key) ? triangles[key] : 0.0}});
    rows.push_back({static_cast<double>(i), s, ratio});
    categories.push_back(key);
    bars.Y.push_back(s);
  }
  // The abdomen is other data: against its absolute target, not the labelmap's baseline.
  if (fastest.count("abdomen_bone")) {
    const double s = fastest["abdomen_bone"];
    std::printf("%-45s %7.3f s  (target < 5 s)  %ld triangles\n", "abdomen CT 512x512x134, --preset bone", s,
                static_cast<long>(triangles["abdomen_bone"]));
    doc.push_back({{"config", "abdomen_bone"}, {"label", "abdomen CT 512x512x134, --preset bone (process)"},
                   {"seconds", s}, {"targetSeconds", 5.0}, {"triangles", triangles["abdomen_bone"]}});
  }
  const std::string out = rp::bench::OutputDirectory();
  std::string error;
  rp::bench::WriteCSV(out + "/whole_process.csv", {"config_index", "seconds", "times_baseline"}, rows, error);
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpMeshWholeProcessBenchmark");  // the load after, the steal over the run
  rp::bench::WriteFiguresJSON(out + "/whole_process.json", doc, error);
  rp::bench::ChartOptions chart;
  chart.Title = "roboplan mesh, 512x512x300 two-label .nrrd (gzip): whole process vs Slicer's pipeline";
  chart.YLabel = "seconds (2 cores, fastest of 3)";
  chart.Width = 1200;
  rp::bench::WriteBarChartPNG(out + "/whole_process_seconds.png", categories, {bars}, chart, error);  // names what it wrote
  ReportStartup(out);
  benchmark::Shutdown();
  return 0;
}
