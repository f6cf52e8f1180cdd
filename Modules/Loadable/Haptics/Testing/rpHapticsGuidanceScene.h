#pragma once
// The scene of the Haptics guidance tests (the logic's and the panel's): a bone slab well below a
// straight trajectory along −S through R = A = 0 (entry S = −42, target S = −55), so the stylus
// near the plan touches no tissue and the force is the fixtures' alone; and the session log's rows.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <vtkNew.h>

#include "rpPolyDataTriangleMesh.h"
#include "rpVec3.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"

namespace rptest {

constexpr double EntryS = -42, TargetS = -55;

inline void AddGuidanceScene(vtkRPScene* scene) {
  vtkNew<vtkRPModelNode> slab;  // top face at S = −60
  slab->SetName("Slab");
  slab->SetTissueClass("bone");
  slab->SetHaptic(true);
  slab->SetPolyData(rp::TriangleMeshToPolyData(rp::shapes::Box({-40, -40, -80}, {40, 40, -60})));
  scene->AddNode(slab);
  vtkNew<vtkRPTrajectoryNode> plan;
  plan->SetName("Plan");
  const double entry[3] = {0, 0, EntryS}, target[3] = {0, 0, TargetS};
  plan->SetEntryAndTarget(entry, target);
  scene->AddNode(plan);
}

/// One servo tick of the session log (rpSessionLog.cxx's columns).
struct LogRow {
  double Time = 0;
  rp::Vec3 Hip, Proxy, Force;
  bool Watchdog = false;
};

inline std::vector<LogRow> ReadSessionLog(const std::string& path) {
  std::vector<LogRow> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (cells.size() < 14) continue;
    auto v = [&](size_t i) { return std::stod(cells[i]); };
    LogRow r;
    r.Time = v(0);
    r.Hip = {v(1), v(2), v(3)};
    r.Proxy = {v(4), v(5), v(6)};
    r.Force = {v(7), v(8), v(9)};
    r.Watchdog = cells[13] == "1";
    rows.push_back(r);
  }
  return rows;
}

/// The largest force change between consecutive ticks logged in [from, to] (s); a watchdog trip
/// (the force zeroed on purpose) and the tick after it are left out.
inline double LargestStep(const std::vector<LogRow>& rows, double from, double to) {
  double largest = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].Time < from || rows[i].Time > to || rows[i].Watchdog || rows[i - 1].Watchdog) continue;
    largest = std::fmax(largest, rp::Norm(rows[i].Force - rows[i - 1].Force));
  }
  return largest;
}

}  // namespace rptest
