#include "rpBenchmarkConditions.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include <sched.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <vtkSMPTools.h>

#include "rpBenchmarkChart.h"
#include "rpChartsDrawEntries.h"
#include "rpStrings.h"

namespace rp::bench {
namespace {

// The first line of a command's output, or "" (git absent, not a repository).
std::string CommandLine(const std::string& command) {
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) return "";
  char buffer[512] = {0};
  const bool read = std::fgets(buffer, sizeof(buffer), pipe) != nullptr;
  pclose(pipe);
  return read ? Trim(buffer) : "";
}

// The commit the build was made from (written at each build), and the source tree's now if it moved.
std::string GitCommit() {
  std::ifstream in(ROBOPLAN_BUILD_COMMIT_FILE);
  std::string built;
  std::getline(in, built);
  built = Trim(built);
  const std::string git = "git -C '" + std::string(ROBOPLAN_SOURCE_DIR) + "' ";
  std::string now = CommandLine(git + "rev-parse --short=12 HEAD");
  if (!now.empty() && !CommandLine(git + "status --porcelain --untracked-files=no").empty()) {
    now += " (with uncommitted changes)";
  }
  if (built.empty()) built = "unknown";
  if (now.empty() || now == built) return built;
  return built + " (source tree now at " + now + ")";
}

std::string ReadCpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) return Trim(line.substr(line.find(':') + 1));
  }
  return "unknown";
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string Loads(const double load[3]) {
  if (load[0] < 0) return "unknown";
  return Fixed(load[0], 2) + " " + Fixed(load[1], 2) + " " + Fixed(load[2], 2) + " (1, 5, 15 min)";
}

std::string Threads() {
  cpu_set_t set;
  CPU_ZERO(&set);
  const int usable = sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : -1;
  std::string text = std::to_string(std::thread::hardware_concurrency()) + " hardware, " +
                     std::to_string(usable) + " usable; VTK SMP " + vtkSMPTools::GetBackend() + " " +
                     std::to_string(vtkSMPTools::GetEstimatedNumberOfThreads());
  if (const char* lp = std::getenv("LP_NUM_THREADS")) text += "; LP_NUM_THREADS=" + std::string(lp);
  return text;
}

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Conditions& Conditions::Process() {
  static Conditions conditions;
  return conditions;
}

Conditions::CpuTicks Conditions::ReadCpuTicks() {
  // cpu  user nice system idle iowait irq softirq steal guest guest_nice (USER_HZ ticks)
  std::ifstream in("/proc/stat");
  std::string cpu;
  unsigned long long v[8] = {0};
  CpuTicks ticks;
  if (!(in >> cpu) || cpu != "cpu") return ticks;
  for (auto& value : v) in >> value;
  for (auto value : v) ticks.Total += value;
  ticks.Idle = v[3] + v[4];
  ticks.Steal = v[7];
  return ticks;
}

void Conditions::Start() {
  this->IsStarted = true;
  this->IsFinished = false;
  this->Date = UtcNow();
  this->Commit = GitCommit();
  this->CpuModel = ReadCpuModel();
  if (getloadavg(this->LoadBefore, 3) != 3) this->LoadBefore[0] = -1;
  // The display (a private Xvfb without one) and the GL driver, so that the run's context names
  // them; a benchmark that draws notes its own window later (NoteRenderWindow).
  this->ProbeGL();
  this->TicksBefore = ReadCpuTicks();
  this->WallBefore = WallSeconds();
}

void Conditions::Finish() {
  if (getloadavg(this->LoadAfter, 3) != 3) this->LoadAfter[0] = -1;
  this->TicksAfter = ReadCpuTicks();
  this->WallAfter = WallSeconds();
  this->IsFinished = true;
}

void Conditions::NoteRenderWindow(vtkRenderWindow* window) {
  std::string report, error;
  if (const auto glReport = draw::Entry<draw::GLReportFunction>("roboplan_gl_report", error)) glReport(window, report);
  this->NoteGLReport(report);
}

void Conditions::NoteGLReport(const std::string& report) {
  auto field = [&report](const std::string& key) {
    const size_t at = report.find(key);
    if (at == std::string::npos) return std::string();
    const size_t end = report.find('\n', at);
    return Trim(report.substr(at + key.size(), end == std::string::npos ? std::string::npos : end - at - key.size()));
  };
  this->GLRenderer = field("OpenGL renderer string:");
  this->GLVersion = field("OpenGL version string:");
}

// A 16x16 offscreen window, drawn once (libRoboPlanChartsDraw.so), for its context's renderer and version.
void Conditions::ProbeGL() {
  std::string report, error;
  const auto probe = draw::Entry<draw::ProbeGLFunction>("roboplan_probe_gl", error);
  if (!probe || !probe(report, error)) {
    this->GLRenderer = "none (" + error + ")";
    return;
  }
  this->NoteGLReport(report);
}

std::vector<std::pair<std::string, std::string>> Conditions::Fields() const {
  std::vector<std::pair<std::string, std::string>> fields = {
      {"date", this->Date},
      {"git commit", this->Commit},
      {"build type", std::string(ROBOPLAN_BUILD_TYPE) +
#ifdef __OPTIMIZE__
                         " (optimized)"
#else
                         " (not optimized)"
#endif
                         + (std::string(ROBOPLAN_SANITIZE).empty() ? "" : ", sanitizer " + std::string(ROBOPLAN_SANITIZE)) +
                         ", " + ROBOPLAN_COMPILER},
      {"cpu model", this->CpuModel},
      {"threads", Threads()},
      {"load average before", Loads(this->LoadBefore)}};
  if (QuickRun())
    fields.emplace_back("run", "quick (ROBOPLAN_BENCHMARK_QUICK): smallest sizes and shortest times, a check that "
                               "every figure is written; not figures to quote");
  XDisplayInfo display;  // none opened unless the drawing half, which opens displays, is loaded
  std::string error;
  if (const auto current = draw::Entry<draw::CurrentXDisplayFunction>("roboplan_current_x_display", error, true))
    current(display);
  fields.emplace_back("screen", display.Name.empty() ? "none opened"
                                                      : display.Name + " " + std::to_string(display.Width) + "x" +
                                                            std::to_string(display.Height) + "x" +
                                                            std::to_string(display.Depth) +
                                                            (display.Private ? " (private Xvfb)" : ""));
  if (!this->GLRenderer.empty()) {
    fields.emplace_back("gl renderer", this->GLRenderer);
    fields.emplace_back("gl version", this->GLVersion.empty() ? "unknown" : this->GLVersion);
  }
  if (this->IsFinished) {
    fields.emplace_back("load average after", Loads(this->LoadAfter));
    const double hz = static_cast<double>(sysconf(_SC_CLK_TCK));
    const double total = static_cast<double>(this->TicksAfter.Total - this->TicksBefore.Total);
    const double idle = static_cast<double>(this->TicksAfter.Idle - this->TicksBefore.Idle);
    const double steal = static_cast<double>(this->TicksAfter.Steal - this->TicksBefore.Steal);
    fields.emplace_back("run seconds", Fixed(this->WallAfter - this->WallBefore, 1));
    fields.emplace_back("steal seconds", Fixed(steal / hz, 2) + " of " + Fixed(total / hz, 1) + " CPU-seconds");
    fields.emplace_back("machine busy", total > 0 ? Fixed(100.0 * (total - idle) / total, 1) + " % of all CPUs (this "
                                                        "process included)"
                                                  : "unknown");
  }
  return fields;
}

std::string Conditions::Text() const {
  std::string text;
  for (const auto& [name, value] : this->Fields()) text += name + ": " + value + "\n";
  return text;
}

bool QuickRun() {
  const char* quick = std::getenv("ROBOPLAN_BENCHMARK_QUICK");
  return quick && *quick && std::string(quick) != "0";
}

void StartConditions() {
  Conditions& conditions = Conditions::Process();
  conditions.Start();
  std::istringstream lines(conditions.Text());
  for (std::string line; std::getline(lines, line);) std::cerr << "[conditions] " << line << "\n";
}

std::string ConditionsJson() {
  nlohmann::json doc = nlohmann::json::object();
  for (const auto& [name, value] : Conditions::Process().Fields()) doc[name] = value;
  return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);  // a CPU or GL name need not be UTF-8
}

void FinishConditions(const std::string& directory, const std::string& program) {
  Conditions& conditions = Conditions::Process();
  if (!conditions.Started()) conditions.Start();
  conditions.Finish();
  std::istringstream lines(conditions.Text());
  for (std::string line; std::getline(lines, line);) std::cerr << "[conditions] " << line << "\n";
  std::string error;
  WriteFigureFile(directory + "/" + program + "-conditions.json", ConditionsJson() + "\n", error);  // warns itself
}

}  // namespace rp::bench
