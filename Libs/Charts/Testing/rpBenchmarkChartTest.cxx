// The chart helper draws what it is given: a red line on white lands in the PNG.
#include <gtest/gtest.h>

#include <filesystem>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "rpBenchmarkChart.h"

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
