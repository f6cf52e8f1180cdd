// The chart helper draws what it is given: a red line on white lands in the PNG.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkSmartPointer.h>

#include "rpBenchmarkChart.h"

namespace {
vtkSmartPointer<vtkImageData> ReadPNG(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

// The longest run of the first series' blue along X (rows y in [from, to)) or along Y (columns x
// in [from, to)) of a chart read back (the PNG's y grows upwards).
int LongestBlueRun(vtkImageData* image, bool alongX, int from, int to) {
  int dims[3];
  image->GetDimensions(dims);
  const int length = alongX ? dims[0] : dims[1];
  int longest = 0;
  for (int line = from; line < to; ++line) {
    int run = 0;
    for (int i = 0; i < length; ++i) {
      auto* p = static_cast<unsigned char*>(image->GetScalarPointer(alongX ? i : line, alongX ? line : i, 0));
      run = (p[0] < 60 && p[1] > 100 && p[1] < 140 && p[2] > 160) ? run + 1 : 0;
      longest = std::max(longest, run);
    }
  }
  return longest;
}
}  // namespace

TEST(BenchmarkChart, WritesAPNGWithTheSeriesColours) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  const std::string path = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/chart.png";
  std::string error;
  rp::bench::Series a{"time", {1, 2, 3, 4}, {1, 4, 9, 16}};
  rp::bench::Series b{"error", {1, 2, 3, 4}, {16, 9, 4, 1}, true};
  rp::bench::ChartOptions options{"Test chart", "N", "value"};
  ASSERT_TRUE(rp::bench::WriteChartPNG(path, {a, b}, options, error)) << error;
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  int dims[3];
  reader->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 900);
  EXPECT_EQ(dims[1], 600);
  // Count pixels of the first series' blue and the second's red.
  int blue = 0, red = 0;
  auto countColours = [&] {
    blue = red = 0;
    auto* image = reader->GetOutput();
    for (int y = 0; y < dims[1]; ++y) {
      for (int x = 0; x < dims[0]; ++x) {
        auto* p = static_cast<unsigned char*>(image->GetScalarPointer(x, y, 0));
        blue += (p[0] < 60 && p[1] > 100 && p[1] < 140 && p[2] > 160);
        red += (p[0] > 190 && p[1] < 60 && p[2] < 60);
      }
    }
  };
  countColours();
  EXPECT_GT(blue, 200);
  EXPECT_GT(red, 50);
  // Grouped bars: blue (first series) and red (second) bars in every category.
  const std::string bars = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/bars.png";
  rp::bench::Series asked{"requested", {}, {0.7, 0.42, 0.03}}, got{"rendered", {}, {0.4, 0.4, 0.03}};
  ASSERT_TRUE(rp::bench::WriteBarChartPNG(bars, {"bone", "cartilage", "fat"}, {asked, got}, options, error)) << error;
  reader->SetFileName(bars.c_str());
  reader->Modified();
  reader->Update();
  countColours();
  EXPECT_GT(blue, 2000);
  EXPECT_GT(red, 1000);
  EXPECT_FALSE(rp::bench::WriteBarChartPNG(bars, {"bone"}, {asked}, options, error));  // 3 values, 1 category
  EXPECT_NE(error.find("3 values for 1 categories"), std::string::npos) << error;

  std::vector<std::vector<double>> rows{{1, 2}, {3, 4}};
  EXPECT_TRUE(rp::bench::WriteCSV(std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/t.csv", {"a", "b"}, rows, error));
  EXPECT_FALSE(rp::bench::WriteCSV(std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/t.csv", {"a"}, rows, error));
}

// The legend (top right, opaque) must not hide the top of a tall bar beneath it: a bar twice as
// high as another shows twice as many pixels, even with four series in the legend.
TEST(BenchmarkChart, TheLegendLeavesTheTallestBarWhole) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  const std::string path = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/bars-legend.png";
  std::string error;
  std::vector<rp::bench::Series> series{{"first, blue", {}, {0.5, 0.1, 0.1, 1.0}},
                                        {"second, with a name as long as benchmarks give theirs", {}, {0.1, 0.1, 0.1, 0.1}},
                                        {"third", {}, {0.1, 0.1, 0.1, 0.1}},
                                        {"fourth", {}, {0.1, 0.1, 0.1, 0.1}}};
  rp::bench::ChartOptions options{"Legend over the bars", "", "value"};
  ASSERT_TRUE(rp::bench::WriteBarChartPNG(path, {"a", "b", "c", "d"}, series, options, error)) << error;
  const vtkSmartPointer<vtkImageData> image = ReadPNG(path);
  int dims[3];
  image->GetDimensions(dims);
  // The longest vertical run of the first series' blue in each half of the picture: the 0.5 bar
  // on the left, the 1.0 bar (under the legend) on the right.
  const int half = LongestBlueRun(image, false, 0, dims[0] / 2), whole = LongestBlueRun(image, false, dims[0] / 2, dims[0]);
  ASSERT_GT(half, 100);
  EXPECT_NEAR(whole, 2 * half, 4) << "the 1.0 bar shows " << whole << " px against " << half << " px for 0.5";
}

// Horizontal bars (ChartOptions::HorizontalBars, for many or long category names): the first
// category is the top row, a bar's length is its value, and the legend (top right) hides none of
// the first bar, the longest.
TEST(BenchmarkChart, HorizontalBarsListTheFirstCategoryOnTopAndRunAlongX) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  const std::string path = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/bars-horizontal.png";
  std::string error;
  std::vector<rp::bench::Series> series{{"first, blue", {}, {1.0, 0.1, 0.1, 0.5}},
                                        {"second, with a name as long as benchmarks give theirs", {}, {0.1, 0.1, 0.1, 0.1}}};
  rp::bench::ChartOptions options{"Horizontal bars", "", "value"};
  options.HorizontalBars = true;
  ASSERT_TRUE(rp::bench::WriteBarChartPNG(path, {"register-volumes", "phantom-registration", "b", "c"}, series, options,
                                          error))
      << error;
  const vtkSmartPointer<vtkImageData> image = ReadPNG(path);
  int dims[3];
  image->GetDimensions(dims);
  const int bottom = LongestBlueRun(image, true, 0, dims[1] / 2), top = LongestBlueRun(image, true, dims[1] / 2, dims[1]);
  ASSERT_GT(bottom, 100);
  EXPECT_NEAR(top, 2 * bottom, 4) << "the first category's 1.0 bar (top) shows " << top << " px against " << bottom
                                  << " px for the last one's 0.5 (bottom)";
}
