// Charts where a user runs a benchmark: without an X display (issue 30). Before, VTK's X render
// window died in XSync (SIGSEGV) after the benchmark had done its work. Now a chart is drawn on a
// private Xvfb (1920x1080x24), and where none can be had it is skipped with the reason, never a
// crash. Each case runs in a child process of its own (a death test's clean re-execution): the
// display is found once per process. ctest runs this test with DISPLAY empty, outside Xvfb.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkConditions.h"
#include "rpXDisplay.h"

namespace {

std::string OutputPath(const std::string& name) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/" + name;
}

bool DrawChart(const std::string& path, std::string& error) {
  std::filesystem::remove(path);
  rp::bench::Series line{"time", {1, 2, 3, 4}, {1, 4, 9, 16}};
  return rp::bench::WriteChartPNG(path, {line}, rp::bench::ChartOptions{"headless", "N", "value"}, error);
}

// Pixels of the first series' blue in a PNG.
int BluePixels(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  int dims[3];
  reader->GetOutput()->GetDimensions(dims);
  int blue = 0;
  for (int y = 0; y < dims[1]; ++y) {
    for (int x = 0; x < dims[0]; ++x) {
      auto* p = static_cast<unsigned char*>(reader->GetOutput()->GetScalarPointer(x, y, 0));
      blue += (p[0] < 60 && p[1] > 100 && p[1] < 140 && p[2] > 160);
    }
  }
  return blue;
}

bool XvfbOnPath() { return std::system("command -v Xvfb >/dev/null 2>&1") == 0; }

}  // namespace

TEST(BenchmarkChartHeadless, AChartWithoutADisplayIsDrawnOnAPrivateXvfb) {
  if (!XvfbOnPath()) GTEST_SKIP() << "Xvfb is not on PATH (package xvfb)";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        unsetenv("DISPLAY");
        std::string error;
        const std::string path = OutputPath("headless-chart.png");
        const bool drawn = DrawChart(path, error);
        const rp::XDisplayInfo display = rp::CurrentXDisplay();
        std::cerr << "drawn " << drawn << " error '" << error << "' blue " << (drawn ? BluePixels(path) : 0)
                  << " screen " << display.Width << "x" << display.Height << "x" << display.Depth << " private "
                  << display.Private << " DISPLAY " << (std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "-");
        std::exit(drawn && BluePixels(path) > 200 ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "drawn 1 error '' blue [0-9]+ screen 1920x1080x24 private 1 DISPLAY :[0-9]+");
}

TEST(BenchmarkChartHeadless, ADisplayThatDoesNotAnswerIsNamedAndTheChartDrawnOnAPrivateXvfb) {
  if (!XvfbOnPath()) GTEST_SKIP() << "Xvfb is not on PATH (package xvfb)";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        setenv("DISPLAY", ":987654", 1);
        std::string error;
        const std::string path = OutputPath("unreachable-display.png");
        const bool drawn = DrawChart(path, error);
        const rp::XDisplayInfo display = rp::CurrentXDisplay();
        std::cerr << "drawn " << drawn << " blue " << (drawn ? BluePixels(path) : 0) << " private " << display.Private
                  << " refused '" << display.Refused << "'";
        std::exit(drawn && BluePixels(path) > 200 ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "drawn 1 blue [0-9]+ private 1 refused 'cannot open the X display ':987654'");
}

TEST(BenchmarkChartHeadless, ADisplayThatDoesNotAnswerAndNoXvfbSkipsTheChartNamingBoth) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        setenv("DISPLAY", ":987654", 1);
        setenv("PATH", ROBOPLAN_TEST_OUTPUT_DIR, 1);  // no Xvfb there
        std::string error;
        const bool drawn = DrawChart(OutputPath("unreachable-display.png"), error);
        std::cerr << "drawn " << drawn << ": " << error;
        std::exit(!drawn ? 0 : 1);
      },
      ::testing::ExitedWithCode(0),
      "drawn 0: picture '.*unreachable-display.png' not drawn: no X display for offscreen pictures: cannot open the X "
      "display ':987654' \\(tried for 5 s\\) and no Xvfb could be started");
}

TEST(BenchmarkChartHeadless, NoDisplayAndNoXvfbSkipsTheChartNamingBoth) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        unsetenv("DISPLAY");
        setenv("PATH", ROBOPLAN_TEST_OUTPUT_DIR, 1);  // no Xvfb there
        std::string error;
        const bool drawn = DrawChart(OutputPath("no-xvfb.png"), error);
        std::cerr << "drawn " << drawn << ": " << error;
        std::exit(drawn ? 1 : 0);
      },
      ::testing::ExitedWithCode(0), "drawn 0: .* no X display \\(\\$DISPLAY is not set\\) and no Xvfb could be started");
}

TEST(BenchmarkChartHeadless, TheConditionsNameTheScreenAndTheGLRendererAfterAHeadlessRun) {
  if (!XvfbOnPath()) GTEST_SKIP() << "Xvfb is not on PATH (package xvfb)";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        unsetenv("DISPLAY");
        rp::bench::Conditions& conditions = rp::bench::Conditions::Process();
        conditions.Start();  // probes GL on the private Xvfb
        conditions.Finish();
        std::cerr << conditions.Text();
        std::exit(0);
      },
      ::testing::ExitedWithCode(0),
      "git commit: .*\nbuild type: .*\ncpu model: .*\nthreads: [0-9]+ hardware.*\nload average before: .*\n"
      "screen: :[0-9]+ 1920x1080x24 \\(private Xvfb\\)\ngl renderer: .+\ngl version: [0-9].*\n"
      "load average after: .*\nrun seconds: .*\nsteal seconds: .*");
}
