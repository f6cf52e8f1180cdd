#include "rpBenchmarkChart.h"

#include <array>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpAtomicFile.h"
#include "rpBenchmarkConditions.h"
#include "rpChartsDrawEntries.h"

namespace rp::bench {
namespace {

const unsigned char Palette[][3] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
                                    {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}};


// Every figure file is written through here (the writer boundary): what the writer throws (VTK's
// allocations, the JSON library, the file system) or returns false for becomes `false` and an
// `error` that names the file; never an abort. In a benchmark each file is named on stderr,
// written or not.
bool Guarded(const std::string& path, std::string& error, const std::function<bool(std::string&)>& write) {
  std::string why;
  bool written = false;
  try {
    written = write(why);
  } catch (const std::exception& e) {
    why = e.what();
  } catch (...) {
    why = "unknown exception";
  }
  const bool benchmark = Conditions::Process().Started();
  if (written) {
    if (benchmark) std::cerr << "[figures] wrote " << path << "\n";
    return true;
  }
  if (why.empty()) why = "the writer gave no reason";
  error = why.find(path) == std::string::npos ? "figure '" + path + "' not written: " + why : why;
  if (benchmark) std::cerr << "[figures] warning: " << error << "\n";
  return false;
}


// The CSV's text: the conditions as '#' lines in a benchmark, the header, the rows.
bool FormatCSV(const std::vector<std::string>& header, const std::vector<std::vector<double>>& rows, std::string& text,
               std::string& error) {
  std::ostringstream out;
  // A benchmark's CSV names its conditions (rpBenchmarkConditions.h) in comment lines.
  if (Conditions::Process().Started()) {
    for (const auto& [name, value] : Conditions::Process().Fields()) out << "# " << name << ": " << value << "\n";
  }
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  out.precision(10);
  for (const auto& row : rows) {
    if (row.size() != header.size()) {
      error = "a row with " + std::to_string(row.size()) + " values, the header has " + std::to_string(header.size());
      return false;
    }
    for (size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << row[i];
    out << "\n";
  }
  text = out.str();
  return true;
}

}  // namespace

std::array<unsigned char, 3> SeriesColor(size_t index) {
  const unsigned char* c = Palette[index % 8];
  return {c[0], c[1], c[2]};
}

bool WriteChartPNG(const std::string& path, const std::vector<Series>& series, const ChartOptions& options,
                   std::string& error) {
  return Guarded(path, error, [&](std::string& why) {
    const auto drawChart = draw::Entry<draw::ChartFunction>("roboplan_draw_chart", why);
    return drawChart && drawChart(path, series, options, why);
  });
}

bool WriteHistogramPNG(const std::string& path, const std::vector<double>& binCenters,
                       const std::vector<double>& counts, const ChartOptions& options, std::string& error) {
  return Guarded(path, error, [&](std::string& why) {
    const auto drawChart = draw::Entry<draw::HistogramFunction>("roboplan_draw_histogram", why);
    return drawChart && drawChart(path, binCenters, counts, options, why);
  });
}

bool WriteBarChartPNG(const std::string& path, const std::vector<std::string>& categories,
                      const std::vector<Series>& series, const ChartOptions& options, std::string& error) {
  return Guarded(path, error, [&](std::string& why) {
    const auto drawChart = draw::Entry<draw::BarChartFunction>("roboplan_draw_bar_chart", why);
    return drawChart && drawChart(path, categories, series, options, why);
  });
}

bool OpenDrawingDisplay(std::string& error) {
  const auto ensure = draw::Entry<draw::EnsureXDisplayFunction>("roboplan_ensure_x_display", error);
  return ensure && ensure(error);
}

bool WriteCSV(const std::string& path, const std::vector<std::string>& header,
              const std::vector<std::vector<double>>& rows, std::string& error) {
  return Guarded(path, error, [&](std::string& why) {
    std::string text;
    return FormatCSV(header, rows, text, why) && WriteFileAtomically(path, text, why);
  });
}

bool WriteFiguresJSON(const std::string& path, const nlohmann::json& figures, std::string& error) {
  return Guarded(path, error, [&](std::string& why) {
    nlohmann::json document = figures.is_object() ? figures : nlohmann::json::object();
    if (!figures.is_object() && !figures.is_null()) document["results"] = figures;
    document["conditions"] = nlohmann::json::parse(ConditionsJson());
    // Text that is not UTF-8 (a device's name, a path) is replaced, not thrown.
    return WriteFileAtomically(path, document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", why);
  });
}

bool WriteFigureFile(const std::string& path, const std::string& text, std::string& error) {
  return Guarded(path, error, [&](std::string& why) { return WriteFileAtomically(path, text, why); });
}

std::string OutputDirectory() {
  const char* env = std::getenv("ROBOPLAN_BENCHMARK_OUTPUT");
  const std::string dir = env && *env ? env : "benchmark-output";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec && !std::filesystem::is_directory(dir)) {
    static bool warned = false;  // once: every figure then names itself
    if (!warned) std::cerr << "[figures] warning: cannot make the output folder '" << dir << "': " << ec.message() << "\n";
    warned = true;
  }
  return dir;
}

}  // namespace rp::bench
