// Volumes benchmarks, each against the way a user would otherwise do it, in the same run:
//  - reading a DICOM series: RoboPlan's DCMTK reader vs ITK's GDCM series reader
//    (itk::ImageSeriesReader + GDCMImageIO + GDCMSeriesFileNames), same files, same voxels;
//  - decode speed (MB/s) of every transfer syntax: the real knee CT (shared/data, 60 slices)
//    re-encoded by the packages' tools, read by both (RoboPlan: DCMTK or GDCM per syntax);
//  - CT-MR registration on the knee phantom: multi-resolution (ours) vs the same ITK v4
//    components at a single resolution, from starts up to 30 degrees / 40 mm off: final error at
//    the bone surface and time (capture range);
//  - phantom generation, small and full.
// Figures (CSV, JSON) and charts (PNG) go to $ROBOPLAN_BENCHMARK_OUTPUT (./benchmark-output). A
// quick run (ROBOPLAN_BENCHMARK_QUICK): a series of 64 pixels, 4 slices in two syntaxes, one
// registration start, no phantom generation timed.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageSeriesReader.h>
#include <nlohmann/json.hpp>
#include <vtkTransform.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpDicomSeries.h"
#include "rpDicomTestTools.h"
#include "rpDicomWriter.h"
#include "rpKneePhantom.h"
#include "rpVolumeRegistration.h"

namespace fs = std::filesystem;
using namespace rp;

namespace {

struct Case {
  int n;  // in-plane size; slices = n / 2
  fs::path dir;
  long voxels;
};
std::vector<Case>& Cases() {
  static std::vector<Case> cases;
  return cases;
}

void PrepareCases() {
  const fs::path root = fs::path(bench::OutputDirectory()) / "dicom-series";
  for (int n : bench::QuickRun() ? std::vector<int>{64} : std::vector<int>{64, 128, 256, 512}) {
    KneePhantomOptions options;
    options.CTDimensions = {n, n, n / 2};
    const double s = 153.6 / n;
    options.CTSpacing = {s, s, 2.0 * s};
    options.GenerateMR = false;
    options.GenerateLabels = false;
    KneePhantom phantom;
    std::string error;
    if (!GenerateKneePhantom(options, phantom, error)) throw std::runtime_error(error);
    const fs::path dir = root / ("ct" + std::to_string(n));
    fs::remove_all(dir);
    if (!WriteDicomSeries(phantom.CT, dir.string(), {}, error)) throw std::runtime_error(error);
    Cases().push_back({n, dir, long(n) * n * (n / 2)});
  }
}

double ReadOurs(const fs::path& dir) {
  ImageVolume v;
  std::string error;
  if (!ReadDicomVolume(dir.string(), v, error)) throw std::runtime_error(error);
  return v.Image->GetScalarComponentAsDouble(1, 1, 1, 0);
}

double ReadItk(const fs::path& dir) {
  using ImageType = itk::Image<short, 3>;
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetDirectory(dir.string());
  const auto uids = names->GetSeriesUIDs();
  auto reader = itk::ImageSeriesReader<ImageType>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(names->GetFileNames(uids.front()));
  reader->Update();
  ImageType::IndexType index = {{1, 1, 1}};
  return reader->GetOutput()->GetPixel(index);
}

// The series of a benchmark's argument; none (and the benchmark skipped) past a quick run's.
const Case* CaseOf(benchmark::State& state) {
  if (size_t(state.range(0)) < Cases().size()) return &Cases()[size_t(state.range(0))];
  state.SkipWithError("no such series in a quick run");
  return nullptr;
}

void BM_ReadDicomRoboPlan(benchmark::State& state) {
  const Case* found = CaseOf(state);
  if (!found) return;
  const Case& c = *found;
  for (auto _ : state) benchmark::DoNotOptimize(ReadOurs(c.dir));
  state.counters["voxels"] = double(c.voxels);
}
void BM_ReadDicomITKGDCM(benchmark::State& state) {
  const Case* found = CaseOf(state);
  if (!found) return;
  const Case& c = *found;
  for (auto _ : state) benchmark::DoNotOptimize(ReadItk(c.dir));
  state.counters["voxels"] = double(c.voxels);
}
BENCHMARK(BM_ReadDicomRoboPlan)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->MinTime(0.5);
BENCHMARK(BM_ReadDicomITKGDCM)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->MinTime(0.5);

// One encoded copy of the real knee CT per transfer syntax and tool.
struct CodecCase {
  std::string Name;
  fs::path Dir;
  double Megabytes = 0.0;  // decoded 16-bit pixel data
};
std::vector<CodecCase>& CodecCases() {
  static std::vector<CodecCase> cases;
  return cases;
}

void PrepareCodecCases() {
  const fs::path source = fs::path(ROBOPLAN_SHARED_DATA_DIR) / "knee-ct-vhf" / "dicom";
  if (!fs::exists(source)) {
    std::fprintf(stderr, "no %s: decode speed per transfer syntax not measured\n", source.c_str());
    return;
  }
  const std::vector<fs::path> files = rp::testing::DicomFiles(source, bench::QuickRun() ? 4 : 60);
  const fs::path root = fs::path(bench::OutputDirectory()) / "dicom-codecs";
  fs::create_directories(root);
  const std::string log = (root / "tools.log").string(), dcmodify = rp::testing::FindTool("dcmodify");
  size_t encoders = bench::QuickRun() ? 2 : rp::testing::DicomEncoders().size();
  for (const rp::testing::DicomEncoder& e : rp::testing::DicomEncoders()) {
    if (encoders-- == 0) break;
    const std::string tool = rp::testing::FindTool(e.Tool);
    if (tool.empty() || (!e.Prepare.empty() && dcmodify.empty())) {
      std::fprintf(stderr, "%s: %s not installed (Debian package %s), not measured\n", e.Name.c_str(), e.Tool.c_str(),
                   e.Package.c_str());
      continue;
    }
    const fs::path dir = root / e.Name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    bool ok = true;
    for (const fs::path& file : files) {
      std::string in = file.string();
      const fs::path copy = root / ("prepared-" + file.filename().string());
      if (!e.Prepare.empty()) {
        fs::copy_file(file, copy, fs::copy_options::overwrite_existing);
        ok = ok && std::system(("\"" + dcmodify + "\" " + e.Prepare + " \"" + copy.string() + "\" >>\"" + log + "\" 2>&1").c_str()) == 0;
        in = copy.string();
      }
      ok = ok && rp::testing::Encode(e, tool, in, (dir / file.filename()).string(), log) == 0;
      fs::remove(copy);
    }
    if (!ok) {
      std::fprintf(stderr, "%s: encoding failed (see %s), not measured\n", e.Name.c_str(), log.c_str());
      continue;
    }
    ImageVolume v;
    std::string error;
    if (!ReadDicomVolume(dir.string(), v, error)) throw std::runtime_error(e.Name + ": " + error);
    CodecCases().push_back({e.Name, dir, v.Image->GetNumberOfPoints() * 2.0 / 1e6});
  }
}

// "jpegls-lossless-dcmcjpls" → "JLS LL (d)": chart labels that fit under their bars.
std::string ShortLabel(std::string name) {
  const std::pair<const char*, const char*> replacements[] = {
      {"-dcmcjpls", " (d)"}, {"-dcmcrle", " (d)"}, {"-dcmconv", " (d)"}, {"-gdcm", " (g)"}, {"jpegls", "JLS"},
      {"jpeg", "JPEG"}, {"j2k", "J2K"}, {"-lossless", " LL"}, {"-lossy", " lossy"}, {"-near", " near"},
      {"-baseline", " base"}, {"-extended", " ext"}, {"-sv1", " SV1"}, {"-p14", " P14"}, {"implicit-little", "implicit"},
      {"explicit-little", "explicit"}, {"explicit-big", "big endian"}, {"deflated", "deflate"}, {"rle", "RLE"},
      {"raw", "raw"}};
  for (const auto& [from, to] : replacements)
    if (const size_t at = name.find(from); at != std::string::npos) name.replace(at, std::strlen(from), to);
  return name;
}

void RegisterCodecBenchmarks() {
  for (size_t i = 0; i < CodecCases().size(); ++i) {
    const CodecCase c = CodecCases()[i];
    benchmark::RegisterBenchmark(("BM_DecodeRoboPlan/" + c.Name).c_str(), [c](benchmark::State& state) {
      for (auto _ : state) benchmark::DoNotOptimize(ReadOurs(c.Dir));
      state.SetBytesProcessed(int64_t(state.iterations() * c.Megabytes * 1e6));
    })->Unit(benchmark::kMillisecond)->MinTime(0.3);
    benchmark::RegisterBenchmark(("BM_DecodeITKGDCM/" + c.Name).c_str(), [c](benchmark::State& state) {
      for (auto _ : state) benchmark::DoNotOptimize(ReadItk(c.Dir));
      state.SetBytesProcessed(int64_t(state.iterations() * c.Megabytes * 1e6));
    })->Unit(benchmark::kMillisecond)->MinTime(0.3);
  }
}

double Seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  PrepareCases();
  PrepareCodecCases();
  RegisterCodecBenchmarks();
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  const std::string dir = bench::OutputDirectory();
  std::string error;
  nlohmann::json figures;

  // ---- DICOM read: same files, both readers, timed here for the chart (median of 3).
  bench::Series ours{"RoboPlan (DCMTK)", {}, {}}, itk{"ITK ImageSeriesReader + GDCM", {}, {}};
  std::vector<std::vector<double>> readRows;
  for (const Case& c : Cases()) {
    double a = 1e9, b = 1e9;
    for (int r = 0; r < (c.voxels > 20000000 ? 1 : 3); ++r) {
      a = std::min(a, Seconds([&] { ReadOurs(c.dir); }));
      b = std::min(b, Seconds([&] { ReadItk(c.dir); }));
    }
    ours.X.push_back(c.voxels / 1e6);
    ours.Y.push_back(a * 1e3);
    itk.X.push_back(c.voxels / 1e6);
    itk.Y.push_back(b * 1e3);
    readRows.push_back({double(c.voxels), a * 1e3, b * 1e3, b / a});
    figures["dicomRead"].push_back({{"voxels", c.voxels}, {"roboplanMs", a * 1e3}, {"itkGdcmMs", b * 1e3}});
  }
  bench::WriteCSV(dir + "/volumes_dicom_read.csv", {"voxels", "roboplan_ms", "itk_gdcm_ms", "itk_over_roboplan"},
                  readRows, error);
  bench::ChartOptions readChart;
  readChart.Title = "Reading a CT DICOM series (one file per slice)";
  readChart.XLabel = "million voxels";
  readChart.YLabel = "time (ms, best of 3; 1 run above 20 M voxels)";
  readChart.LogX = readChart.LogY = true;
  bench::WriteChartPNG(dir + "/volumes_dicom_read.png", {ours, itk}, readChart, error);

  // ---- Decode speed per transfer syntax (best of 3), both readers, same files.
  if (!CodecCases().empty()) {
    std::vector<std::string> names;
    bench::Series oursMBs{"RoboPlan (DCMTK, or GDCM for JPEG 2000 / JPEG-LS)", {}, {}},
        itkMBs{"ITK ImageSeriesReader + GDCMImageIO", {}, {}};
    std::vector<std::vector<double>> rows;
    std::printf("\ndecode speed, knee CT (%.1f MB of 16-bit pixels):\n", CodecCases().front().Megabytes);
    for (size_t i = 0; i < CodecCases().size(); ++i) {
      const CodecCase& c = CodecCases()[i];
      double a = 1e9, b = 1e9;
      double va = 0, vb = 0;
      for (int r = 0; r < 3; ++r) {
        a = std::min(a, Seconds([&] { va = ReadOurs(c.Dir); }));
        b = std::min(b, Seconds([&] { vb = ReadItk(c.Dir); }));
      }
      names.push_back(ShortLabel(c.Name));
      oursMBs.Y.push_back(c.Megabytes / a);
      itkMBs.Y.push_back(c.Megabytes / b);
      rows.push_back({double(i), c.Megabytes / a, c.Megabytes / b});
      figures["decodeMBs"].push_back({{"syntax", c.Name}, {"roboplan", c.Megabytes / a}, {"itkGdcm", c.Megabytes / b},
                                      {"sameVoxel", va == vb}});
      std::printf("  %-26s RoboPlan %7.1f MB/s   ITK+GDCM %7.1f MB/s%s\n", c.Name.c_str(), c.Megabytes / a,
                  c.Megabytes / b, va == vb ? "" : "   (voxel (1,1,1) differs!)");
    }
    bench::WriteCSV(dir + "/volumes_decode_codecs.csv", {"codec_index", "roboplan_mb_s", "itk_gdcm_mb_s"}, rows, error);
    bench::ChartOptions codecChart;
    codecChart.Title = "Decoding a real CT series (knee, 60 slices) per transfer syntax";
    codecChart.YLabel = "MB/s of decoded pixels (best of 3)";
    codecChart.XLabel = "transfer syntax (encoder: (d) DCMTK tool, (g) gdcmconv)";
    codecChart.Width = 1800;
    bench::WriteBarChartPNG(dir + "/volumes_decode_codecs.png", names, {oursMBs, itkMBs}, codecChart, error);
  }

  // ---- Registration capture range: multi-resolution vs single resolution, same starts.
  KneePhantomOptions options;
  options.GenerateLabels = false;
  KneePhantom phantom;
  if (!GenerateKneePhantom(options, phantom, error)) return 1;
  const double bounds[6] = {-75, 75, -75, 75, -78, 78};
  std::vector<std::array<double, 3>> surface;
  for (auto s : {KneeStructure::Femur, KneeStructure::Tibia, KneeStructure::Patella, KneeStructure::Fibula}) {
    const auto p = phantom.Model->SurfacePoints(s, 500, bounds);
    surface.insert(surface.end(), p.begin(), p.end());
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  bench::Series multi{"multi-resolution 8-4-2-1 (RoboPlan)", {}, {}, true},
      single{"single resolution (ITK v4, same metric/optimizer)", {}, {}, true};
  std::vector<std::vector<double>> regRows;
  for (int trial = 0; trial < (bench::QuickRun() ? 1 : 8); ++trial) {
    const double angle = 4.0 * trial, shift = 5.0 * trial;  // up to 28 degrees, 35 mm
    double axis[3] = {unit(rng), unit(rng), unit(rng)}, dir3[3] = {unit(rng), unit(rng), unit(rng)};
    const double dn = std::sqrt(dir3[0] * dir3[0] + dir3[1] * dir3[1] + dir3[2] * dir3[2]);
    vtkNew<vtkTransform> start;
    start->PostMultiply();
    start->RotateWXYZ(angle, axis);
    start->Translate(shift * dir3[0] / dn, shift * dir3[1] / dn, shift * dir3[2] / dn);
    start->Concatenate(phantom.CTToMR);
    RigidRegistrationOptions o;
    o.InitialFixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();
    o.InitialFixedToMoving->DeepCopy(start->GetMatrix());
    const double startError = TransformRMSDifference(o.InitialFixedToMoving, phantom.CTToMR, surface);
    RigidRegistrationResult a, b;
    RegisterVolumesRigid(phantom.CT, phantom.MR, o, a, error);
    RigidRegistrationOptions s1 = o;
    s1.ShrinkFactors = {1};
    s1.SmoothingSigmasMM = {0.0};
    RegisterVolumesRigid(phantom.CT, phantom.MR, s1, b, error);
    const double ea = TransformRMSDifference(a.FixedToMoving, phantom.CTToMR, surface);
    const double eb = TransformRMSDifference(b.FixedToMoving, phantom.CTToMR, surface);
    multi.X.push_back(startError);
    multi.Y.push_back(std::max(ea, 1e-3));
    single.X.push_back(startError);
    single.Y.push_back(std::max(eb, 1e-3));
    regRows.push_back({angle, shift, startError, ea, a.Seconds, double(a.Converged), eb, b.Seconds, double(b.Converged)});
    figures["registration"].push_back({{"startDegrees", angle},
                                       {"startMM", shift},
                                       {"startRMS", startError},
                                       {"multiResRMS", ea},
                                       {"multiResSeconds", a.Seconds},
                                       {"multiResConverged", a.Converged},
                                       {"singleResRMS", eb},
                                       {"singleResSeconds", b.Seconds},
                                       {"singleResConverged", b.Converged}});
    std::printf("start %5.1f deg %5.1f mm (%6.2f mm RMS): multi %.3f mm %.2f s | single %.3f mm %.2f s\n", angle, shift,
                startError, ea, a.Seconds, eb, b.Seconds);
  }
  bench::WriteCSV(dir + "/volumes_registration.csv",
                  {"start_deg", "start_mm", "start_rms_mm", "multi_rms_mm", "multi_s", "multi_converged",
                   "single_rms_mm", "single_s", "single_converged"},
                  regRows, error);
  bench::ChartOptions regChart;
  regChart.Title = "CT-MR registration on the knee phantom: error at the bone surface";
  regChart.XLabel = "start error (mm RMS at the bone surface)";
  regChart.YLabel = "final error (mm RMS)";
  regChart.LogY = true;
  bench::WriteChartPNG(dir + "/volumes_registration.png", {multi, single}, regChart, error);

  // ---- Phantom generation.
  for (auto size : bench::QuickRun() ? std::vector<KneePhantomSize>{}
                                     : std::vector<KneePhantomSize>{KneePhantomSize::Small, KneePhantomSize::Full}) {
    KneePhantomOptions p;
    p.Size = size;
    KneePhantom out;
    const double t = Seconds([&] { GenerateKneePhantom(p, out, error); });
    figures["phantom"][size == KneePhantomSize::Small ? "smallSeconds" : "fullSeconds"] = t;
    std::printf("phantom %s: %.2f s\n", size == KneePhantomSize::Small ? "small" : "full", t);
  }
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpVolumesBenchmark");  // the load after, the steal over the run
  bench::WriteFiguresJSON(dir + "/volumes_benchmark.json", figures, error);
  return 0;
}
