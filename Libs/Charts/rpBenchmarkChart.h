#pragma once
// Figures and charts for benchmarks and reports: CSV tables and PNG line/scatter charts drawn
// with VTK's chart classes in an offscreen window. Debian's VTK draws through GLX: without
// $DISPLAY a private Xvfb is started for the process (rpXDisplay.h); where none can be, a picture
// is not drawn and the Write*PNG call returns false with the reason (never a crash).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

class vtkRenderWindow;

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
};

/// Draws the series into a PNG. Returns false and sets `error` on failure.
bool WriteChartPNG(const std::string& path, const std::vector<Series>& series, const ChartOptions& options,
                   std::string& error);

/// The colour (RGB 0-255) WriteChartPNG draws its index-th series in (tests look for it).
std::array<unsigned char, 3> SeriesColor(size_t index);

/// Histogram as bars (bin centres in X, counts in Y).
bool WriteHistogramPNG(const std::string& path, const std::vector<double>& binCenters,
                       const std::vector<double>& counts, const ChartOptions& options, std::string& error);

/// Grouped bars: one group per category (labelled on the X axis), one bar per series in each
/// group (each series' Y holds one value per category; X is not used), e.g. requested against
/// rendered stiffness per tissue.
bool WriteBarChartPNG(const std::string& path, const std::vector<std::string>& categories,
                      const std::vector<Series>& series, const ChartOptions& options, std::string& error);

/// Renders an offscreen window and writes what it shows as a PNG (charts, pictures). Without an X
/// display (rp::EnsureXDisplay) it returns false naming why and renders nothing.
bool WriteWindowPNG(vtkRenderWindow* window, const std::string& path, std::string& error);

/// Writes a CSV with a header row; every row must have header.size() values. In a benchmark
/// (Conditions::Process() started) the conditions come first as '#' comment lines.
bool WriteCSV(const std::string& path, const std::vector<std::string>& header,
              const std::vector<std::vector<double>>& rows, std::string& error);

/// $ROBOPLAN_BENCHMARK_OUTPUT or ./benchmark-output (created).
std::string OutputDirectory();

}  // namespace rp::bench
