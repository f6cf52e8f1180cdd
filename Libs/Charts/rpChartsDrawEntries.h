#pragma once
// The entries of libRoboPlanChartsDraw.so (rpChartDrawing.cxx) that RoboPlanCharts resolves on
// first use (rp::SiblingLibraryFunction): their names and types, in one place for both sides.
#include <string>
#include <vector>

#include "rpBenchmarkChart.h"
#include "rpSiblingLibrary.h"
#include "rpXDisplay.h"

class vtkRenderWindow;

#define RP_CHARTS_DRAW_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::bench::draw {
constexpr const char* Library = "libRoboPlanChartsDraw.so";
using ChartFunction = bool (*)(const std::string&, const std::vector<Series>&, const ChartOptions&, std::string&);
using HistogramFunction = bool (*)(const std::string&, const std::vector<double>&, const std::vector<double>&,
                                   const ChartOptions&, std::string&);
using BarChartFunction = bool (*)(const std::string&, const std::vector<std::string>&, const std::vector<Series>&,
                                  const ChartOptions&, std::string&);
using GLReportFunction = void (*)(vtkRenderWindow*, std::string&);
using ProbeGLFunction = bool (*)(std::string&, std::string&);
using CurrentXDisplayFunction = void (*)(rp::XDisplayInfo&);
using EnsureXDisplayFunction = bool (*)(std::string&);

/// The entry `symbol` of the library beside RoboPlanCharts (used by RoboPlanCharts only: the anchor
/// is its own code), loaded on first use; nullptr with `error` naming the library's path and why.
template <typename Function>
Function Entry(const char* symbol, std::string& error, bool onlyIfLoaded = false) {
  std::string why;
  const auto function = SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&Entry<Function>), Library,
                                                         symbol, why, onlyIfLoaded);
  if (!function && !why.empty()) error = "charts and pictures cannot be drawn: " + why;
  return function;
}
}  // namespace rp::bench::draw
