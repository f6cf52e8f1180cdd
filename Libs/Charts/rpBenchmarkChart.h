#pragma once
// Figures and charts for benchmarks and reports: CSV tables, JSON figures and PNG line/scatter
// charts drawn with VTK's chart classes in an offscreen window. Debian's VTK draws through GLX:
// without $DISPLAY a private Xvfb is started for the process (rpXDisplay.h); where none can be, a
// picture is not drawn and the Write*PNG call returns false with the reason.
// A figure that cannot be written is never an abort: every Write* call catches what its writers
// throw and returns false with `error` naming the file and why. In a benchmark (its conditions
// started, rpBenchmarkConditions.h) each call also prints "[figures] wrote <path>" or "[figures]
// warning: <error>" on stderr, so that a figure lost is named even where the caller ignores the
// result. CSV and JSON files are written atomically (no half file is left).
// The charts are drawn by libRoboPlanChartsDraw.so (rpChartDrawing.cxx), loaded on the first chart:
// this library maps no VTK rendering, so linking it costs a command nothing until it draws. Where
// that library is missing, a Write*PNG call returns false with an error naming the file.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>


namespace rp::bench {

struct Series {
  std::string Name;
  std::vector<double> X, Y;
  bool Points = false;  // scatter (true) or line with markers (false)
};

struct ChartOptions {
  std::string Title, XLabel, YLabel;
  bool LogX = false, LogY = false;
  int Width = 900, Height = 600;
  /// Bar charts: bars along X, one category a row down the left axis (the first at the top), for
  /// many or long category names; YLabel then titles the values' axis, at the bottom.
  bool HorizontalBars = false;
};

/// Draws the series into a PNG. Returns false and sets `error` on failure.
bool WriteChartPNG(const std::string& path, const std::vector<Series>& series, const ChartOptions& options,
                   std::string& error);

/// The colour (RGB 0-255) WriteChartPNG draws its index-th series in (tests look for it).
std::array<unsigned char, 3> SeriesColor(size_t index);

/// Histogram as bars (bin centres in X, counts in Y).
bool WriteHistogramPNG(const std::string& path, const std::vector<double>& binCenters,
                       const std::vector<double>& counts, const ChartOptions& options, std::string& error);

/// Grouped bars: one group per category (labelled on the X axis, or down the left one with
/// ChartOptions::HorizontalBars), one bar per series in each group (each series' Y holds one value
/// per category; X is not used), e.g. requested against rendered stiffness per tissue.
bool WriteBarChartPNG(const std::string& path, const std::vector<std::string>& categories,
                      const std::vector<Series>& series, const ChartOptions& options, std::string& error);


/// An X display to draw on (rp::EnsureXDisplay, rpXDisplay.h, in libRoboPlanChartsDraw.so, loaded
/// here): for a caller that checks once before a group of pictures. False with `error` naming why.
bool OpenDrawingDisplay(std::string& error);

/// Writes a CSV with a header row; every row must have header.size() values. In a benchmark
/// (Conditions::Process() started) the conditions come first as '#' comment lines.
bool WriteCSV(const std::string& path, const std::vector<std::string>& header,
              const std::vector<std::vector<double>>& rows, std::string& error);

/// Writes a benchmark's figures as one JSON object: the keys of `figures` (a list or a single value
/// goes under "results") and "conditions", the run's conditions (rpBenchmarkConditions.h; call
/// FinishConditions first for the "after" fields).
bool WriteFiguresJSON(const std::string& path, const nlohmann::json& figures, std::string& error);

/// Writes a figure file of another kind (its whole text), the same way.
bool WriteFigureFile(const std::string& path, const std::string& text, std::string& error);

/// $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output, created (where it cannot be, a warning names
/// it and every figure written there is then a named warning).
std::string OutputDirectory();

}  // namespace rp::bench
