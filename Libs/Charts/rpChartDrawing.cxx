// The drawing half of Libs/Charts (libRoboPlanChartsDraw.so): VTK's chart classes and offscreen
// render windows, which map VTK's rendering, the chart stack (vtkChartsCore, vtkInfovisCore and
// through them vtkParallelMPI and Open MPI) and GL. RoboPlanCharts' WriteChartPNG, WriteHistogramPNG
// and WriteBarChartPNG load it on the first chart (its entries below), so a command that writes no
// picture never maps it; code that renders itself (pictures, the viewer, benchmarks) links it.
#include <filesystem>
#include <string>
#include <vector>

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
#include <vtkPlotBar.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "rpBenchmarkChart.h"
#include "rpChartsDrawEntries.h"
#include "rpWindowPicture.h"
#include "rpXDisplay.h"

namespace rp::bench {
namespace {

bool Render(vtkContextView* view, const std::string& path, const ChartOptions& options, std::string& error) {
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(options.Width, options.Height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  return WriteWindowPNG(view->GetRenderWindow(), path, error);
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
  const bool horizontal = options.HorizontalBars;
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  StyleChart(chart, options);
  if (horizontal) {  // the values along the bottom, the categories down the left
    chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(options.YLabel);
    chart->GetAxis(vtkAxis::LEFT)->SetTitle(options.XLabel);
  }
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
  const size_t n = categories.size();
  // A category's place on its axis: left to right, or top to bottom (the axis grows upwards).
  auto place = [&](size_t i) { return static_cast<double>(horizontal ? n - 1 - i : i); };
  for (size_t i = 0; i < n; ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, place(i));
    for (size_t j = 0; j < series.size(); ++j) {
      table->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(j + 1), series[j].Y[i]);
      top = std::max(top, series[j].Y[i]);
    }
  }
  for (size_t j = 0; j < series.size(); ++j) {
    vtkPlot* bars = chart->AddPlot(vtkChart::BAR);
    if (horizontal) vtkPlotBar::SafeDownCast(bars)->SetOrientation(vtkPlotBar::HORIZONTAL);
    bars->SetInputData(table, 0, static_cast<vtkIdType>(j + 1));
    const auto c = SeriesColor(j);
    bars->SetColor(c[0], c[1], c[2], 255);
  }
  vtkNew<vtkDoubleArray> ticks;
  vtkNew<vtkStringArray> labels;
  for (size_t i = 0; i < n; ++i) {
    ticks->InsertNextValue(place(i));
    labels->InsertNextValue(categories[i]);
  }
  vtkAxis* categoryAxis = chart->GetAxis(horizontal ? vtkAxis::LEFT : vtkAxis::BOTTOM);
  categoryAxis->SetCustomTickPositions(ticks, labels);
  categoryAxis->SetBehavior(vtkAxis::FIXED);
  vtkAxis* valueAxis = chart->GetAxis(horizontal ? vtkAxis::BOTTOM : vtkAxis::LEFT);
  valueAxis->SetBehavior(vtkAxis::FIXED);
  // The legend sits at the top right, over the plot (about 18 px a series plus its frame, of a plot
  // area some 80 px shorter than the picture): vertical bars leave the tallest room below it,
  // horizontal ones leave a free row band above the first category.
  const double legendShare = std::min(0.5, (18.0 * static_cast<double>(series.size()) + 24.0) /
                                               std::max(1.0, options.Height - 80.0));
  const double span = static_cast<double>(n) + 0.2;
  categoryAxis->SetRange(-0.6, static_cast<double>(n) - 0.4 + (horizontal ? span * legendShare / (1.0 - legendShare) : 0.0));
  valueAxis->SetRange(0, top > 0 ? 1.05 * top / (horizontal ? 1.0 : 1.0 - legendShare) : 1.0);
  return Render(view, path, options, error);
}

}  // namespace

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

}  // namespace rp::bench

RP_CHARTS_DRAW_ENTRY bool roboplan_draw_chart(const std::string& path, const std::vector<rp::bench::Series>& series,
                                              const rp::bench::ChartOptions& options, std::string& error) {
  return rp::bench::DrawChart(path, series, options, error);
}

RP_CHARTS_DRAW_ENTRY bool roboplan_draw_histogram(const std::string& path, const std::vector<double>& binCenters,
                                                  const std::vector<double>& counts,
                                                  const rp::bench::ChartOptions& options, std::string& error) {
  return rp::bench::DrawHistogram(path, binCenters, counts, options, error);
}

RP_CHARTS_DRAW_ENTRY bool roboplan_draw_bar_chart(const std::string& path, const std::vector<std::string>& categories,
                                                  const std::vector<rp::bench::Series>& series,
                                                  const rp::bench::ChartOptions& options, std::string& error) {
  return rp::bench::DrawBars(path, categories, series, options, error);
}

// What the GL context of a window that rendered reports (vtkRenderWindow::ReportCapabilities).
RP_CHARTS_DRAW_ENTRY void roboplan_gl_report(vtkRenderWindow* window, std::string& report) {
  report = window ? window->ReportCapabilities() : "";
}

// A 16x16 offscreen window, drawn once, for its context's report; false with `error` without a display.
RP_CHARTS_DRAW_ENTRY bool roboplan_probe_gl(std::string& report, std::string& error) {
  vtkNew<vtkRenderWindow> window;
  if (!rp::PrepareOffscreenWindow(window, error)) return false;
  vtkNew<vtkRenderer> background;
  window->SetSize(16, 16);
  window->AddRenderer(background);
  window->Render();
  report = window->ReportCapabilities();
  return true;
}

RP_CHARTS_DRAW_ENTRY void roboplan_current_x_display(rp::XDisplayInfo& display) { display = rp::CurrentXDisplay(); }

RP_CHARTS_DRAW_ENTRY bool roboplan_ensure_x_display(std::string& error) { return rp::EnsureXDisplay(error); }
