#include "rpBenchmarkChart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkStringArray.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "rpAtomicFile.h"
#include "rpBenchmarkConditions.h"
#include "rpXDisplay.h"

namespace rp::bench {
namespace {

const unsigned char Palette[][3] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
                                    {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}};

bool Render(vtkContextView* view, const std::string& path, const ChartOptions& options, std::string& error) {
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(options.Width, options.Height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  return WriteWindowPNG(view->GetRenderWindow(), path, error);
}

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

void StyleChart(vtkChartXY* chart, const ChartOptions& options) {
  chart->SetTitle(options.Title);
  chart->GetTitleProperties()->SetFontSize(18);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(options.XLabel);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(options.YLabel);
  chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(options.LogX);
  chart->GetAxis(vtkAxis::LEFT)->SetLogScale(options.LogY);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
}

bool DrawChart(const std::string& path, const std::vector<Series>& series, const ChartOptions& options,
               std::string& error) {
  if (series.empty()) {
    error = "no series to draw";
    return false;
  }
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  StyleChart(chart, options);
  size_t index = 0;
  for (const Series& s : series) {
    if (s.X.size() != s.Y.size() || s.X.empty()) {
      error = "series '" + s.Name + "' has no points or unequal X/Y lengths";
      return false;
    }
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> x, y;
    x->SetName("x");
    y->SetName(s.Name.c_str());
    table->AddColumn(x);
    table->AddColumn(y);
    // A plot with one point has empty bounds and VTK draws nothing: repeat it a hair away.
    const bool single = s.X.size() == 1;
    table->SetNumberOfRows(static_cast<vtkIdType>(s.X.size() + (single ? 1 : 0)));
    for (size_t i = 0; i < s.X.size(); ++i) {
      table->SetValue(static_cast<vtkIdType>(i), 0, s.X[i]);
      table->SetValue(static_cast<vtkIdType>(i), 1, s.Y[i]);
    }
    if (single) {
      table->SetValue(1, 0, s.X[0] * (1 + 1e-3) + 1e-9);
      table->SetValue(1, 1, s.Y[0]);
    }
    vtkPlot* plot = chart->AddPlot(s.Points ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    const auto c = SeriesColor(index++);
    plot->SetColor(c[0], c[1], c[2], 255);
    plot->SetWidth(2.0);
    if (auto* points = vtkPlotPoints::SafeDownCast(plot)) points->SetMarkerStyle(vtkPlotPoints::CIRCLE);
  }
  // Fit the axes to every series (VTK's automatic range can miss a series added last).
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const Series& s : series) {
    for (size_t i = 0; i < s.X.size(); ++i) {
      if (options.LogX && s.X[i] <= 0) continue;
      if (options.LogY && s.Y[i] <= 0) continue;
      lo[0] = std::min(lo[0], s.X[i]), hi[0] = std::max(hi[0], s.X[i]);
      lo[1] = std::min(lo[1], s.Y[i]), hi[1] = std::max(hi[1], s.Y[i]);
    }
  }
  const int axes[2] = {vtkAxis::BOTTOM, vtkAxis::LEFT};
  const bool logs[2] = {options.LogX, options.LogY};
  for (int a = 0; a < 2; ++a) {
    if (lo[a] > hi[a] || logs[a]) continue;
    const double pad = hi[a] > lo[a] ? 0.05 * (hi[a] - lo[a]) : std::max(1e-9, 0.05 * std::abs(hi[a]));
    chart->GetAxis(axes[a])->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(axes[a])->SetRange(lo[a] - pad, hi[a] + pad);
  }
  return Render(view, path, options, error);
}

bool DrawHistogram(const std::string& path, const std::vector<double>& binCenters, const std::vector<double>& counts,
                   const ChartOptions& options, std::string& error) {
  if (binCenters.size() != counts.size() || binCenters.empty()) {
    error = "histogram has no bins or unequal lengths";
    return false;
  }
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  StyleChart(chart, options);
  chart->SetShowLegend(false);
  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> x, y;
  x->SetName("bin");
  y->SetName("count");
  table->AddColumn(x);
  table->AddColumn(y);
  table->SetNumberOfRows(static_cast<vtkIdType>(counts.size()));
  for (size_t i = 0; i < counts.size(); ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, binCenters[i]);
    table->SetValue(static_cast<vtkIdType>(i), 1, counts[i]);
  }
  vtkPlot* bars = chart->AddPlot(vtkChart::BAR);
  bars->SetInputData(table, 0, 1);
  bars->SetColor(31, 119, 180, 255);
  return Render(view, path, options, error);
}

bool DrawBars(const std::string& path, const std::vector<std::string>& categories, const std::vector<Series>& series,
              const ChartOptions& options, std::string& error) {
  if (categories.empty() || series.empty()) {
    error = "the bar chart has no categories or no series";
    return false;
  }
  for (const Series& s : series) {
    if (s.Y.size() != categories.size()) {
      error = "series '" + s.Name + "' has " + std::to_string(s.Y.size()) + " values for " +
              std::to_string(categories.size()) + " categories";
      return false;
    }
  }
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  StyleChart(chart, options);
  chart->SetBarWidthFraction(0.8f);  // vtkChartXY puts bar plots of the same X side by side
  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> x;
  x->SetName("category");
  table->AddColumn(x);
  for (const Series& s : series) {
    vtkNew<vtkDoubleArray> y;
    y->SetName(s.Name.c_str());
    table->AddColumn(y);
  }
  table->SetNumberOfRows(static_cast<vtkIdType>(categories.size()));
  double top = 0;
  for (size_t i = 0; i < categories.size(); ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, static_cast<double>(i));
    for (size_t j = 0; j < series.size(); ++j) {
      table->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(j + 1), series[j].Y[i]);
      top = std::max(top, series[j].Y[i]);
    }
  }
  for (size_t j = 0; j < series.size(); ++j) {
    vtkPlot* bars = chart->AddPlot(vtkChart::BAR);
    bars->SetInputData(table, 0, static_cast<vtkIdType>(j + 1));
    const unsigned char* c = Palette[j % 8];
    bars->SetColor(c[0], c[1], c[2], 255);
  }
  vtkNew<vtkDoubleArray> ticks;
  vtkNew<vtkStringArray> labels;
  for (size_t i = 0; i < categories.size(); ++i) {
    ticks->InsertNextValue(static_cast<double>(i));
    labels->InsertNextValue(categories[i]);
  }
  vtkAxis* bottom = chart->GetAxis(vtkAxis::BOTTOM);
  bottom->SetCustomTickPositions(ticks, labels);
  bottom->SetBehavior(vtkAxis::FIXED);
  bottom->SetRange(-0.6, static_cast<double>(categories.size()) - 0.4);
  vtkAxis* left = chart->GetAxis(vtkAxis::LEFT);
  left->SetBehavior(vtkAxis::FIXED);
  // The legend sits at the top right, over the plot: leave the tallest bar room below it (about
  // 18 px a series plus its frame, of a plot area some 80 px shorter than the picture).
  const double legendShare = std::min(0.5, (18.0 * static_cast<double>(series.size()) + 24.0) /
                                               std::max(1.0, options.Height - 80.0));
  left->SetRange(0, top > 0 ? 1.05 * top / (1.0 - legendShare) : 1.0);
  return Render(view, path, options, error);
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
  return Guarded(path, error, [&](std::string& why) { return DrawChart(path, series, options, why); });
}

bool WriteHistogramPNG(const std::string& path, const std::vector<double>& binCenters,
                       const std::vector<double>& counts, const ChartOptions& options, std::string& error) {
  return Guarded(path, error, [&](std::string& why) { return DrawHistogram(path, binCenters, counts, options, why); });
}

bool WriteBarChartPNG(const std::string& path, const std::vector<std::string>& categories,
                      const std::vector<Series>& series, const ChartOptions& options, std::string& error) {
  return Guarded(path, error, [&](std::string& why) { return DrawBars(path, categories, series, options, why); });
}

bool WriteWindowPNG(vtkRenderWindow* window, const std::string& path, std::string& error) {
  std::string why;
  if (!rp::PrepareOffscreenWindow(window, why)) {  // never VTK's own X connection (rpXDisplay.h)
    error = "picture '" + path + "' not drawn: " + why;
    return false;
  }
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0 || !std::filesystem::exists(path)) {
    error = "could not write the picture '" + path + "'";
    return false;
  }
  return true;
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
