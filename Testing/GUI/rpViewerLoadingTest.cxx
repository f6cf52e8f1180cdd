// The viewer loads without blocking (GUI test under Xvfb): a 512x512x300 DICOM series, written
// at test time into the build tree by our DICOM writer, is read on a worker thread while a
// 10 Hz QTimer keeps firing; the reader's per-file progress reaches the progress dialog; Cancel
// leaves the scene unchanged; a failing read names the problem and changes nothing.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <QApplication>
#include <QProgressDialog>
#include <QSurfaceFormat>
#include <QTest>
#include <QTimer>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkImageData.h>

#include "rpDicomWriter.h"
#include "rpImageVolume.h"
#include "rpViewerMainWindow.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

QApplication& Application() {
  static int argc = 1;
  static char name[] = "rpViewerLoadingTest";
  static char* argv[] = {name, nullptr};
  static QApplication* application = [] {
    QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
    auto* app = new QApplication(argc, argv);
    QApplication::setOrganizationName("RoboPlanTest");
    QApplication::setApplicationName("rpViewerLoadingTest");
    return app;
  }();
  return *application;
}

// 512 x 512 x 300 CT slices (int16, 0.5 x 0.5 x 1 mm), written once per build tree.
const fs::path& LargeSeries() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(ROBOPLAN_BINARY_DIR) / "Testing" / "Data" / "series-512x512x300";
    if (fs::exists(d / "IM00300.dcm") && !fs::exists(d / "IM00301.dcm")) return d;
    fs::remove_all(d);
    rp::ImageVolume volume;
    volume.Image = vtkSmartPointer<vtkImageData>::New();
    volume.Image->SetDimensions(512, 512, 300);
    volume.Image->AllocateScalars(VTK_SHORT, 1);
    short* v = static_cast<short*>(volume.Image->GetScalarPointer());
    for (int k = 0; k < 300; ++k)
      for (int j = 0; j < 512; ++j)
        for (int i = 0; i < 512; ++i) *v++ = static_cast<short>(((i / 32 + j / 32 + k / 10) % 2) * 1000 - 500);
    volume.IJKToRAS->SetElement(0, 0, -0.5);
    volume.IJKToRAS->SetElement(1, 1, -0.5);
    std::string error;
    EXPECT_TRUE(rp::WriteDicomSeries(volume, d.string(), {}, error)) << error;
    return d;
  }();
  return dir;
}

// Watches the window's progress dialog while a load runs.
struct DialogWatch {
  int MaxValue = -1;
  bool SawPartial = false;  // a value strictly between 0 and the maximum
  QString Label;
};

}  // namespace

TEST(ViewerLoading, LargeSeriesLoadsWhileTheEventLoopServesATimer) {
  Application();
  const fs::path series = LargeSeries();
  vtkNew<vtkRPScene> scene;
  rp::ViewerMainWindow window(nullptr, scene);
  window.resize(900, 700);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));

  std::vector<Clock::time_point> ticks;
  QTimer tenHertz;
  tenHertz.setInterval(100);
  QObject::connect(&tenHertz, &QTimer::timeout, [&]() { ticks.push_back(Clock::now()); });
  DialogWatch watch;
  QTimer watcher;
  watcher.setInterval(20);
  QObject::connect(&watcher, &QTimer::timeout, [&]() {
    if (auto* dialog = window.findChild<QProgressDialog*>()) {
      const int value = dialog->value();
      watch.MaxValue = std::max(watch.MaxValue, value);
      if (value > 0 && value < dialog->maximum()) {
        watch.SawPartial = true;
        watch.Label = dialog->labelText();
      }
    }
  });
  tenHertz.start();
  watcher.start();
  const Clock::time_point start = Clock::now();
  QString error;
  ASSERT_TRUE(window.LoadFile(QString::fromStdString(series.string()), &error)) << error.toStdString();
  const Clock::time_point end = Clock::now();
  tenHertz.stop();
  watcher.stop();

  const auto volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
  ASSERT_EQ(volumes.size(), 1u);
  int dims[3];
  vtkRPScalarVolumeNode::SafeDownCast(volumes[0])->GetImageData()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 512);
  EXPECT_EQ(dims[1], 512);
  EXPECT_EQ(dims[2], 300);

  // The timer kept firing during the load: ticks in proportion to the time, no long gap.
  const double seconds = std::chrono::duration<double>(end - start).count();
  double maxGap = 0.0;
  Clock::time_point previous = start;
  for (const Clock::time_point& t : ticks) {
    if (t > end) break;
    maxGap = std::max(maxGap, std::chrono::duration<double>(t - previous).count());
    previous = t;
  }
  maxGap = std::max(maxGap, std::chrono::duration<double>(end - previous).count());
  std::cout << "load " << seconds << " s, " << ticks.size() << " ticks of a 10 Hz timer, longest gap " << maxGap
            << " s\n";
  EXPECT_GT(seconds, 0.3) << "the load was too quick to tell anything";
  EXPECT_GE(double(ticks.size()), 0.5 * seconds * 10.0 - 1.0);
  EXPECT_LT(maxGap, 1.0);
  // The reader's progress reached the dialog.
  EXPECT_TRUE(watch.SawPartial) << "max value " << watch.MaxValue;
  EXPECT_TRUE(watch.Label.contains("scanning") || watch.Label.contains("reading DICOM")) << watch.Label.toStdString();
}

TEST(ViewerLoading, CancelLeavesTheSceneUnchanged) {
  Application();
  const fs::path series = LargeSeries();
  vtkNew<vtkRPScene> scene;
  rp::ViewerMainWindow window(nullptr, scene);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  const int before = scene->GetNumberOfNodes();
  bool cancelled = false;
  QTimer watcher;
  watcher.setInterval(20);
  QObject::connect(&watcher, &QTimer::timeout, [&]() {
    auto* dialog = window.findChild<QProgressDialog*>();
    if (!cancelled && dialog && dialog->labelText().contains("reading DICOM") && dialog->value() > 0) {
      dialog->cancel();
      cancelled = true;
    }
  });
  watcher.start();
  QString error;
  EXPECT_FALSE(window.LoadFile(QString::fromStdString(series.string()), &error));
  watcher.stop();
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(error.toStdString(), "cancelled");
  EXPECT_EQ(scene->GetNumberOfNodes(), before);

  // A read that fails names the problem and leaves the scene as it was; the next load works.
  const fs::path broken = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "broken.nrrd";
  fs::create_directories(broken.parent_path());
  { std::ofstream(broken) << "NRRD0004\ntype: short\ndimension: 3\nsizes: 100000 100000 100000\nendian: little\nencoding: raw\n\n"; }
  EXPECT_FALSE(window.LoadFile(QString::fromStdString(broken.string()), &error));
  EXPECT_TRUE(error.contains("would need")) << error.toStdString();
  EXPECT_EQ(scene->GetNumberOfNodes(), before);
}
