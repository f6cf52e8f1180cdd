// Memory over a cohort in one process: 50 cases in a row through the same commands the workflow
// runs (read -> bones -> display and haptic meshes -> Dice against the truth), called in-process
// through the module manager the way `roboplan` calls them. Users of other tools report crashes
// after 8-10 cases and split cohorts into batches of 30; here the resident memory must stay flat:
// the second half of the cohort may not use more than the first, and it may not grow per case.
// A leak is judged on the heap bytes in use (malloc's own count, all arenas): resident memory and
// its peak also move with allocator slack (per-thread arenas of VTK's TBB workers differ from
// run to run under load), so they are reported and only checked against gross growth.
#include <gtest/gtest.h>
#include <malloc.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpModuleManager.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace {

// Resident and peak resident memory of this process, MiB (/proc/self/status).
std::pair<double, double> MemoryMiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  double rss = 0, peak = 0;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) rss = std::stod(line.substr(6)) / 1024.0;
    if (line.rfind("VmHWM:", 0) == 0) peak = std::stod(line.substr(6)) / 1024.0;
  }
  return {rss, peak};
}

// Heap bytes handed out by malloc and not yet freed (all arenas, plus mmapped blocks), MiB.
double HeapInUseMiB() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
}

class Cohort {
 public:
  Cohort() {
    this->Manager.LoadModules({ROBOPLAN_BINARY_DIR "/lib/roboplan-modules"}, this->Scene);
  }
  // Runs `roboplan <args> --json` in this process; returns its JSON (null when it printed none).
  nlohmann::json Run(std::vector<std::string> args, int& code) {
    const rp::Command* command = this->Manager.FindCommand(args.front());
    if (!command) throw std::runtime_error("no command " + args.front());
    rp::CommandContext context;
    context.Arguments.assign(args.begin() + 1, args.end());
    context.Arguments.push_back("--json");
    std::ostringstream captured;
    context.Out = &captured;
    code = command->Run(context);
    const std::string text = captured.str();
    return text.empty() ? nlohmann::json() : nlohmann::json::parse(text, nullptr, false);
  }

 private:
  vtkNew<vtkRPScene> Scene;
  rp::ModuleManager Manager;
};

TEST(CohortMemory, FiftyCasesInOneProcessKeepMemoryFlat) {
  const fs::path out = fs::path(ROBOPLAN_TEST_OUTPUT_DIR);
  fs::remove_all(out);
  fs::create_directories(out);
  Cohort cohort;
  int code = 0;
  // Three different cases, round robin: two phantoms (different noise) and the real knee CT when
  // ../shared/data is there (a DICOM series read every third case).
  struct Case {
    std::string Image, Truth;
  };
  std::vector<Case> cases;
  for (int seed : {1, 2}) {
    const fs::path folder = out / ("phantom" + std::to_string(seed));
    auto doc = cohort.Run({"phantom", "--out", folder.string(), "--size", "small", "--seed", std::to_string(seed),
                           "--format", "nrrd"},
                          code);
    ASSERT_EQ(code, 0);
    cases.push_back({doc["ct"]["path"].get<std::string>(), (folder / "labels.nrrd").string()});
  }
  const fs::path knee = fs::path(ROBOPLAN_SHARED_DATA_DIR) / "knee-ct-vhf";
  if (fs::exists(knee / "dicom"))
    cases.push_back({(knee / "dicom").string(), (knee / "labels.nrrd").string()});
  else
    std::cout << "note: " << knee << " is absent: the cohort cycles the two phantoms\n";

  const int count = 50;
  std::vector<double> rss, peak, heap;
  std::ofstream csv(out / "memory.csv");
  csv << "case,input,rss_mib,peak_mib,heap_in_use_mib\n";
  for (int n = 0; n < count; ++n) {
    const Case& c = cases[static_cast<size_t>(n) % cases.size()];
    const fs::path folder = out / "case";
    fs::remove_all(folder);
    const std::string volume = (folder / "volume.nrrd").string();
    fs::create_directories(folder);
    cohort.Run({"convert", c.Image, volume}, code);
    ASSERT_EQ(code, 0) << "case " << n << ": read " << c.Image;
    auto mesh = cohort.Run({"mesh", volume, "--out", (folder / "models").string(), "--preset", "bone", "--keep-largest",
                            "--fill-holes"},
                           code);
    ASSERT_EQ(code, 0) << "case " << n << ": mesh";
    ASSERT_TRUE(mesh["ok"].get<bool>());
    auto score = cohort.Run({"compare-labels", (folder / "models" / "segmentation.seg.nrrd").string(), c.Truth}, code);
    ASSERT_EQ(code, 0) << "case " << n << ": compare-labels";
    ASSERT_GT(score["segments"][0]["dice"].get<double>(), 0.3);
    const auto [now, high] = MemoryMiB();
    rss.push_back(now);
    peak.push_back(high);
    heap.push_back(HeapInUseMiB());
    csv << n + 1 << "," << c.Image << "," << now << "," << high << "," << heap.back() << "\n";
  }
  // Flat: the heap in use does not climb along the second half (least squares over cases 26-50;
  // the cases cycle, so compare like with like), and the peak resident memory of the second half
  // stays near the first half's.
  const int m = count / 2;
  auto slopeOverSecondHalf = [&](const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int n = count - m; n < count; ++n) sx += n, sy += y[n], sxx += double(n) * n, sxy += n * y[n];
    return (m * sxy - sx * sy) / (m * sxx - sx * sx);
  };
  const double heapSlope = slopeOverSecondHalf(heap), rssSlope = slopeOverSecondHalf(rss);
  const double firstHalfPeak = peak[m - 1], lastPeak = peak.back();
  std::cout << "memory over " << count << " cases: heap in use " << heap.front() << " MiB after case 1, " << heap[m - 1]
            << " after case " << m << ", " << heap.back() << " after case " << count << " (slope over the second half "
            << heapSlope * 1024 << " KiB/case); resident " << rss.front() << ", " << rss[m - 1] << ", " << rss.back()
            << " MiB (slope " << rssSlope * 1024 << " KiB/case); peak " << firstHalfPeak << " MiB after case " << m
            << ", " << lastPeak << " after case " << count << " (" << (out / "memory.csv").string() << ")\n";
  // One leaked 146x176x150 short volume per case would be 7.4 MiB/case; a leaked mesh ~1 MiB/case.
  EXPECT_LT(heapSlope * 1024, 32.0) << "heap in use climbs case after case (a leak)";
  EXPECT_LT(heap.back() - heap[m - 1], 2.0) << "heap in use grew over the second half of the cohort";
  EXPECT_LT(lastPeak - firstHalfPeak, 32.0) << "peak memory grew over the second half of the cohort";
}

}  // namespace
