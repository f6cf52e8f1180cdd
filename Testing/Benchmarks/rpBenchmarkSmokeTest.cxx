// Every benchmark runs to its end and writes its figures (issue 44: the two meshing benchmarks
// measured, then aborted on a JSON type error and wrote nothing). Not a timing: one benchmark
// program (argv[1]) run as a user would, quick (ROBOPLAN_BENCHMARK_QUICK: the smallest sizes and
// shortest times, rpBenchmarkConditions.h), four ways at once: with --benchmark_filter=NONE and
// with one cheap case (a minimal --benchmark_min_time), each with the test's X display (ctest runs
// this under its own Xvfb) and without one (DISPLAY unset: the program starts a private Xvfb).
// Known answers: exit 0, no abort; every figure file the program writes (its table below) is there
// and parses: JSON (an object naming the run's conditions), CSV (a header, rows of numbers of its
// width), PNG (the signature, a plausible size, a picture of more than one colour); with nothing
// selected a figure that has nothing to show may be left out, but only with a warning that names
// it ("[figures] warning: ... <file>").
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "rpSharedData.h"

namespace fs = std::filesystem;

extern char** environ;

namespace {

std::string Program;  // the benchmark's path (argv[1])

// What a benchmark writes. `Figures`: every figure file of its quick case (relative to the output
// folder); those marked `*` only with ../shared/data, those marked `+` only by the quick case (a
// picture of what it drew: with nothing selected there is none, and nothing to warn about).
struct Expectation {
  std::string QuickCase;  // the --benchmark_filter of its one cheap case
  std::vector<std::string> Figures;
  std::string SharedData;  // the quick case needs this (relative to the shared data), or ""
};

const std::map<std::string, Expectation>& Expectations() {
  static const std::map<std::string, Expectation> table = {
      {"rpDrillingBenchmark",
       {"BM_OneBlockRecontour$",
        {"drilling_benchmark.json", "drilling_grids.csv", "drilling_time_vs_accuracy.png", "drilling_recontour.png",
         "drilling_tick.png", "drilling_volume_error.png"}, ""}},
      {"rpHapticsBenchmark",
       {"BM_ClosestPoint_BVH$",
        {"haptics_benchmark.json", "haptics_closest_point.csv", "haptics_tick_histogram.png",
         "haptics_stiffness_sweep.csv", "haptics_stiffness_penetration.png", "haptics_stiffness_stability.png",
         "haptics_period_histogram.png", "haptics_period_histogram_spin.png"}, ""}},
      {"rpLandmarkRegistrationBenchmark",
       {"BM_RoboPlanSolve/4$",
        {"landmark_registration_benchmark.json", "landmark_registration_speed.csv", "landmark_registration_speed.png",
         "landmark_registration_tre.csv", "landmark_registration_tre.png"}, ""}},
      {"rpSegmentationToMeshBenchmark",
       {"BM_BoneMesh/gaussian_s1.0_grid0.90/",
        {"segmentation_to_mesh.json", "segmentation_to_mesh.csv", "segmentation_to_mesh_time_vs_error.png"}, ""}},
      {"rpMeshWholeProcessBenchmark",
       {"BM_ReadNrrdGz/|BM_Startup/--help",
        {"whole_process.json", "whole_process.csv", "whole_process_seconds.png", "startup.json", "startup.csv",
         "startup_ms.png"}, ""}},
      {"rpTrackingBenchmark",
       {"BM_NdiParseBx/3$",
        {"tracking_benchmark.json", "tracking_latency_histogram.csv", "tracking_ingestion.csv",
         "tracking_serial_cpu.csv", "tracking_sender_to_scene.csv", "tracking_sender_to_scene_cdf.png",
         "tracking_latency_cdf.png"}, ""}},
      {"rpVolumesBenchmark",
       {"BM_ReadDicomRoboPlan/0",
        {"volumes_benchmark.json", "volumes_dicom_read.csv", "volumes_dicom_read.png", "volumes_registration.csv",
         "volumes_registration.png", "*volumes_decode_codecs.csv", "*volumes_decode_codecs.png"}, ""}},
      {"rpViewerBenchmark",
       {"BM_Viewer4Up_DisplayRate",
        {"viewer-frames.json", "+viewer-frames-display-rate.csv", "viewer-frame-times.png",
         "+viewer-4up-while-touching.png", "+viewer-4up-still.png"}, ""}},
      {"rpSlicePictureBenchmark",
       {"BM_SlicePicture_OnePass/0$", {"slice-picture.csv", "slice-picture.png"}, "knee-ct-vhf/dicom"}},
  };
  return table;
}

std::string Name() { return fs::path(Program).filename().string(); }

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Outcome {
  int ExitCode = -1;  // -1: did not exit (signal or time-out)
  std::string Why;    // when it did not exit
  std::string Output;  // stdout + stderr
  double Seconds = 0;
};

// A run of the benchmark in its own folder (its output folder too), in its own process group.
struct Child {
  pid_t Pid = -1;
  fs::path Log;
  std::chrono::steady_clock::time_point Start;
  Outcome Result;
};

// Starts the benchmark in `folder` with or without $DISPLAY.
Child Start(const fs::path& folder, const std::vector<std::string>& arguments, bool display) {
  std::vector<std::string> args = {Program};
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    if (entry.rfind("ROBOPLAN_BENCHMARK_OUTPUT=", 0) == 0 || (!display && entry.rfind("DISPLAY=", 0) == 0)) continue;
    env.push_back(entry);
  }
  env.push_back("ROBOPLAN_BENCHMARK_OUTPUT=" + folder.string());
  env.push_back("ROBOPLAN_BENCHMARK_QUICK=1");
  std::vector<char*> argv, envp;
  for (auto& a : args) argv.push_back(a.data());
  for (auto& e : env) envp.push_back(e.data());
  argv.push_back(nullptr);
  envp.push_back(nullptr);
  Child child;
  child.Log = folder / "output.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, child.Log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addchdir_np(&actions, folder.c_str());
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);  // its own group: stopped whole
  posix_spawnattr_setpgroup(&attributes, 0);
  child.Start = std::chrono::steady_clock::now();
  const int rc = posix_spawn(&child.Pid, Program.c_str(), &actions, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0) {
    child.Pid = -1;
    child.Result.Why = "cannot start " + Program + ": " + std::strerror(rc);
  }
  return child;
}

// Waits for every child; stops one (and what it started, its process group) after `timeout` s.
void WaitForAll(std::vector<Child*> children, double timeout) {
  const auto start = std::chrono::steady_clock::now();
  for (bool running = true; running;) {
    running = false;
    const bool late = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout;
    for (Child* child : children) {
      if (child->Pid <= 0) continue;
      int status = 0;
      if (waitpid(child->Pid, &status, WNOHANG) == 0) {
        if (!late) {
          running = true;
          continue;
        }
        kill(-child->Pid, SIGKILL);
        waitpid(child->Pid, &status, 0);
        child->Result.Why = "still running after " + std::to_string(int(timeout)) + " s (stopped)";
      } else if (WIFEXITED(status)) {
        child->Result.ExitCode = WEXITSTATUS(status);
      } else {
        child->Result.Why = std::string("killed by signal ") + strsignal(WTERMSIG(status));
      }
      kill(-child->Pid, SIGKILL);  // anything of its group left behind
      child->Result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - child->Start).count();
      child->Result.Output = ReadText(child->Log);
      child->Pid = -1;
    }
    if (running) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// The file's problem as a figure, or "" when it is a good one.
std::string CheckJSON(const fs::path& path) {
  const nlohmann::json document = nlohmann::json::parse(ReadText(path), nullptr, false);
  if (document.is_discarded()) return "is not JSON";
  if (!document.is_object()) return "is not a JSON object";
  const bool conditionsFile = path.filename().string().find("-conditions.json") != std::string::npos;
  const nlohmann::json& conditions = conditionsFile ? document : document.value("conditions", nlohmann::json());
  if (!conditions.is_object() || !conditions.contains("date") || !conditions.contains("git commit"))
    return "does not name the run's conditions";
  if (!conditions.contains("run")) return "does not say it was a quick run";
  return "";
}

bool IsNumber(const std::string& field) {
  if (field == "nan" || field == "-nan" || field == "inf" || field == "-inf") return true;
  char* end = nullptr;
  std::strtod(field.c_str(), &end);
  return !field.empty() && end == field.c_str() + field.size();
}

std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  return fields;
}

std::string CheckCSV(const fs::path& path, bool rowsRequired) {
  std::stringstream lines(ReadText(path));
  std::string line;
  std::vector<std::string> header;
  int rows = 0, comments = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("#", 0) == 0) {
      ++comments;
      continue;
    }
    const std::vector<std::string> fields = Fields(line);
    if (header.empty()) {
      header = fields;
      for (const std::string& name : header)
        if (name.empty() || IsNumber(name)) return "has no header (first line: " + line + ")";
      continue;
    }
    if (fields.size() != header.size())
      return "row " + std::to_string(rows + 1) + " has " + std::to_string(fields.size()) + " values for " +
             std::to_string(header.size()) + " columns";
    for (const std::string& field : fields)
      if (!IsNumber(field)) return "row " + std::to_string(rows + 1) + " holds '" + field + "', not a number";
    ++rows;
  }
  if (header.empty()) return "is empty";
  if (comments == 0) return "does not name the run's conditions ('#' lines)";
  if (rowsRequired && rows == 0) return "has a header and no rows";
  return "";
}

uint32_t BigEndian(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (size_t i = 0; i < 4; ++i) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

std::string CheckPNG(const fs::path& path) {
  const std::string bytes = ReadText(path);
  if (bytes.size() < 2000) return "holds " + std::to_string(bytes.size()) + " bytes: too few for a picture";
  if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return "has no PNG signature";
  if (bytes.compare(12, 4, "IHDR") != 0) return "has no PNG header chunk";
  const uint32_t width = BigEndian(bytes, 16), height = BigEndian(bytes, 20);
  if (width < 200 || height < 150 || width > 5000 || height > 5000)
    return "is " + std::to_string(width) + "x" + std::to_string(height) + " pixels: not a chart's or a view's size";
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] != int(width) || dims[1] != int(height)) return "does not decode to its header's size";
  std::set<uint32_t> colours;
  const int components = image->GetNumberOfScalarComponents();
  const auto* pixels = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (vtkIdType i = 0; i < vtkIdType(width) * height && colours.size() < 3; i += 7) {
    uint32_t colour = 0;
    for (int c = 0; c < std::min(components, 3); ++c) colour = colour << 8 | pixels[i * components + c];
    colours.insert(colour);
  }
  if (colours.size() < 3) return "is blank (fewer than 3 colours)";
  return "";
}

std::string CheckFigure(const fs::path& path, bool rowsRequired) {
  const std::string extension = path.extension().string();
  if (extension == ".json") return CheckJSON(path);
  if (extension == ".csv") return CheckCSV(path, rowsRequired);
  if (extension == ".png") return CheckPNG(path);
  return "";
}

const Expectation& Expected() {
  static const Expectation none;
  const auto found = Expectations().find(Name());
  return found == Expectations().end() ? none : found->second;
}

bool SharedDataPresent(const std::string& relative) { return fs::exists(rptest::SharedDataPath(relative)); }

// The four ways, run at once (most of their time is waiting: servo periods, sockets, Xvfb).
std::string WayName(bool oneCase, bool display) {
  return std::string(oneCase ? "one-case" : "nothing") + (display ? "-display" : "-no-display");
}
fs::path FolderOf(const std::string& way) { return fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / Name() / way; }
std::map<std::string, Child>& Runs() {
  static std::map<std::string, Child> runs;
  return runs;
}

void RunAllWays() {
  const Expectation& expected = Expected();
  std::vector<Child*> children;
  for (bool oneCase : {false, true}) {
    if (oneCase && !expected.SharedData.empty() && !SharedDataPresent(expected.SharedData)) continue;
    for (bool display : {true, false}) {
      const std::string way = WayName(oneCase, display);
      fs::remove_all(FolderOf(way));
      fs::create_directories(FolderOf(way));
      std::vector<std::string> arguments = {"--benchmark_filter=" + (oneCase ? expected.QuickCase : std::string("NONE"))};
      if (oneCase) arguments.push_back("--benchmark_min_time=0.01");
      Runs()[way] = Start(FolderOf(way), arguments, display && std::getenv("DISPLAY"));
      children.push_back(&Runs()[way]);
    }
  }
  WaitForAll(children, 240);
}

// True when a "[figures] warning: " line of the output names `path`.
bool NamedInAWarning(const std::string& output, const fs::path& path) {
  std::stringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("[figures] warning: ", 0) == 0 && line.find(path.string()) != std::string::npos) return true;
  return false;
}

// Checks what the benchmark did and wrote one way.
void Check(bool oneCase, bool display) {
  ASSERT_NE(Expectations().find(Name()), Expectations().end())
      << Name() << " is a benchmark this test does not know: add it to its table";
  const Expectation& expected = Expected();
  if (oneCase && !expected.SharedData.empty()) {
    RP_REQUIRE_SHARED_DATA(expected.SharedData);
  }
  if (display) {
    ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "the test runs on its own X display (run-with-xvfb.sh)";
  }
  const std::string way = WayName(oneCase, display);
  const fs::path folder = FolderOf(way);
  ASSERT_TRUE(Runs().count(way)) << way << " was not run";
  const Outcome& outcome = Runs()[way].Result;
  std::printf("[smoke] %s %s: exit %d in %.1f s\n", Name().c_str(), way.c_str(), outcome.ExitCode, outcome.Seconds);
  const std::string tail = outcome.Output.size() > 3000 ? outcome.Output.substr(outcome.Output.size() - 3000) : outcome.Output;
  ASSERT_TRUE(outcome.Why.empty()) << outcome.Why << "\n" << tail;
  ASSERT_EQ(outcome.ExitCode, 0) << tail;
  EXPECT_EQ(outcome.Output.find("terminate called"), std::string::npos) << tail;
  if (oneCase) {  // Google Benchmark's table of the cases run
    EXPECT_NE(outcome.Output.find("Iterations"), std::string::npos) << "the quick case did not run\n" << tail;
    EXPECT_EQ(outcome.Output.find("ERROR OCCURRED"), std::string::npos) << "the quick case failed\n" << tail;
  }
  // Every figure: written and good, or (nothing selected) named in a warning.
  std::vector<std::string> figures = expected.Figures;
  figures.push_back(Name() + "-conditions.json");
  for (std::string figure : figures) {
    if (figure[0] == '*' && !SharedDataPresent("knee-ct-vhf")) continue;
    if (figure[0] == '+' && !oneCase) continue;
    if (figure[0] == '*' || figure[0] == '+') figure = figure.substr(1);
    const fs::path path = folder / figure;
    if (!fs::exists(path)) {
      EXPECT_TRUE(!oneCase && NamedInAWarning(outcome.Output, path))
          << figure << " was not written" << (NamedInAWarning(outcome.Output, path) ? "" : " and no warning names it")
          << "\n" << tail;
      continue;
    }
    const std::string problem = CheckFigure(path, oneCase);
    EXPECT_TRUE(problem.empty()) << path.string() << " " << problem;
  }
  // And whatever else it wrote beside them.
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string problem = CheckFigure(entry.path(), false);
    EXPECT_TRUE(problem.empty()) << entry.path().string() << " " << problem;
  }
}

class BenchmarkSmoke : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { RunAllWays(); }
};

}  // namespace

TEST_F(BenchmarkSmoke, NothingSelectedWithADisplay) { Check(false, true); }
TEST_F(BenchmarkSmoke, NothingSelectedWithoutADisplay) { Check(false, false); }
TEST_F(BenchmarkSmoke, OneQuickCaseWithADisplay) { Check(true, true); }
TEST_F(BenchmarkSmoke, OneQuickCaseWithoutADisplay) { Check(true, false); }

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <benchmark program> [gtest options]\n", argv[0]);
    return 2;
  }
  Program = argv[1];
  return RUN_ALL_TESTS();
}
