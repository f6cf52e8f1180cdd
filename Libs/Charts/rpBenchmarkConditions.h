#pragma once
// What a benchmark ran on, so that every figure names its conditions (issue 30): a figure that a
// user cannot reproduce is not a result, and on a shared 2-core virtual machine a timing depends on
// the build, the X server, the GL driver and what else ran as much as on the code.
//
// Conditions::Start() records, at the start of a run: the date, the git commit the build was made
// from (and the source tree's, when it moved on since), the build type and compiler, the CPU
// model, the hardware and usable threads and VTK's SMP back-end, the load average and the CPU
// counters of /proc/stat. Finish() records them again at the end:
// the load average after, and over the run the CPU time the hypervisor stole and the share of the
// machine's CPU that was busy. The GL renderer and version come from a small probe window at
// Start() (on the X display rp::EnsureXDisplay finds or starts) or from a render window that drew
// (NoteRenderWindow), with the display's screen size and depth. Fields() lists them as name/value text; the
// benchmarks print them, put them in Google Benchmark's JSON context and their own JSON, and
// rp::bench::WriteCSV writes them as '#' comment lines atop every CSV once Start() ran.
#include <string>
#include <utility>
#include <vector>

class vtkRenderWindow;

namespace rp::bench {

class Conditions {
 public:
  /// The process's record (one per benchmark run).
  static Conditions& Process();

  void Start();
  void Finish();
  bool Started() const { return this->IsStarted; }
  bool Finished() const { return this->IsFinished; }

  /// The GL renderer and version of a window that has rendered (its context is current-able).
  void NoteRenderWindow(vtkRenderWindow* window);

  /// Name/value pairs in a fixed order; "after" fields only once Finish() ran.
  std::vector<std::pair<std::string, std::string>> Fields() const;
  /// One "name: value" line per field.
  std::string Text() const;

 private:
  struct CpuTicks {
    unsigned long long Total = 0, Idle = 0, Steal = 0;
  };
  static CpuTicks ReadCpuTicks();
  void ProbeGL();
  void NoteGLReport(const std::string& report);

  bool IsStarted = false, IsFinished = false;
  std::string Date, Commit, CpuModel;
  double LoadBefore[3] = {-1, -1, -1}, LoadAfter[3] = {-1, -1, -1};
  CpuTicks TicksBefore, TicksAfter;
  double WallBefore = 0, WallAfter = 0;
  std::string GLRenderer, GLVersion;
};

/// A quick run ($ROBOPLAN_BENCHMARK_QUICK set, not "0"): every part of a benchmark runs at its
/// smallest size and shortest time, to check that it runs to its end and writes every figure
/// (the benchmarks' smoke test). Its figures are not results: the conditions say so ("run").
bool QuickRun();

/// Starts the process's record and prints it (stderr, "[conditions] " lines).
void StartConditions();
/// Finishes it, prints it and writes <directory>/<program>-conditions.json (a JSON object).
void FinishConditions(const std::string& directory, const std::string& program);
/// The record as a JSON object text ({"date": ..., ...}) for the benchmarks' own JSON files.
std::string ConditionsJson();

}  // namespace rp::bench
