// The viewer loads without blocking (GUI test under Xvfb): a 512x512x300 DICOM series, written
// at test time into the build tree by our DICOM writer, is read on a worker thread while a
// 20 ms QTimer keeps firing; the reader's per-file progress reaches the progress dialog; Cancel
// leaves the scene unchanged; a failing read names the problem and changes nothing; a scene file,
// whose reader fills the scene, is handed back to the GUI thread and opens.
// No wall-clock bounds (speed belongs in Testing/Benchmarks): the load is off the GUI thread when
// the GUI thread read almost none of the series' bytes (the kernel's per-thread I/O counts) and the
// timer fired at several stages of the read, however slowly a loaded machine runs either thread.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <QApplication>
#include <QProgressDialog>
#include <QSurfaceFormat>
#include <QTest>
#include <QTimer>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpDataLoader.h"
#include "rpDicomWriter.h"
#include "rpImagingReaders.h"
#include "rpImageVolume.h"
#include "rpSceneIO.h"
#include "qRPViewerMainWindow.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// The application, and the imaging readers its viewer module registers at Setup.
QApplication& Application() {
  rp::RegisterImagingReaders();
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

// Bytes read through read()/pread() so far ("rchar" of a /proc/.../io file): by the calling
// thread (/proc/thread-self/io) or by the whole process, its ended threads included
// (/proc/self/io). -1 when the kernel does not count them.
long long BytesRead(const char* ioFile) {
  std::ifstream in(ioFile);
  std::string key;
  long long value = -1;
  while (in >> key >> value)
    if (key == "rchar:") return value;
  return -1;
}

struct FolderBytes {
  long long Total = 0, Smallest = -1;  // of its files
};
FolderBytes SeriesBytes(const fs::path& dir) {
  FolderBytes bytes;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const auto size = static_cast<long long>(entry.file_size());
    bytes.Total += size;
    bytes.Smallest = bytes.Smallest < 0 ? size : std::min(bytes.Smallest, size);
  }
  return bytes;
}

// What a timer on the GUI thread saw of the window's progress dialog while a load ran.
struct DialogWatch {
  int Ticks = 0;
  int MaxValue = -1;
  std::set<int> PartialValues;  // values strictly between 0 and the maximum, one per stage seen
  QString Label;
};

}  // namespace

TEST(ViewerLoading, LargeSeriesLoadsWhileTheEventLoopServesATimer) {
  Application();
  const fs::path series = LargeSeries();
  vtkNew<vtkRPScene> scene;
  qRPViewerMainWindow window(nullptr, scene);
  window.resize(900, 700);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));

  DialogWatch watch;
  QTimer ticker;
  ticker.setInterval(20);
  QObject::connect(&ticker, &QTimer::timeout, [&]() {
    ++watch.Ticks;
    if (auto* dialog = window.findChild<QProgressDialog*>()) {
      const int value = dialog->value();
      watch.MaxValue = std::max(watch.MaxValue, value);
      if (value > 0 && value < dialog->maximum()) {
        watch.PartialValues.insert(value);
        watch.Label = dialog->labelText();
      }
    }
  });
  ticker.start();
  const long long guiBefore = BytesRead("/proc/thread-self/io"), processBefore = BytesRead("/proc/self/io");
  const Clock::time_point start = Clock::now();
  QString error;
  ASSERT_TRUE(window.LoadFile(QString::fromStdString(series.string()), &error)) << error.toStdString();
  const Clock::time_point end = Clock::now();
  const long long guiRead = BytesRead("/proc/thread-self/io") - guiBefore;
  const long long processRead = BytesRead("/proc/self/io") - processBefore;
  ticker.stop();

  const auto volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
  ASSERT_EQ(volumes.size(), 1u);
  int dims[3];
  vtkRPScalarVolumeNode::SafeDownCast(volumes[0])->GetImageData()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 512);
  EXPECT_EQ(dims[1], 512);
  EXPECT_EQ(dims[2], 300);

  std::cout << "load " << std::chrono::duration<double>(end - start).count() << " s (not a result: machine load), "
            << watch.Ticks << " ticks of a 20 ms timer, " << watch.PartialValues.size()
            << " progress stages seen by them; bytes read: " << guiRead << " by the GUI thread, " << processRead
            << " by the process\n";
  // The series was read on another thread: the process read all its bytes, the GUI thread less
  // than one of its files. A load on the GUI thread reads them all there, even one that serves
  // events; finding the reader there (is one of the files a SEG?) read 15 kB of each.
  ASSERT_GE(guiBefore, 0) << "no /proc/thread-self/io: the kernel does not count each thread's reads";
  const FolderBytes seriesBytes = SeriesBytes(series);
  EXPECT_GE(processRead, seriesBytes.Total) << "the reads did not go through read(): nothing to tell the threads apart";
  EXPECT_LT(guiRead, seriesBytes.Smallest) << "the GUI thread read from the series' files itself";
  // The event loop served the timer while the worker was reading: its ticks saw the progress
  // dialog at several stages strictly between the start and the end (a load on the GUI thread
  // lets no tick through until it has ended).
  EXPECT_GE(watch.PartialValues.size(), 3u) << "max value " << watch.MaxValue << ", ticks " << watch.Ticks;
  EXPECT_TRUE(watch.Label.contains("scanning") || watch.Label.contains("reading DICOM")) << watch.Label.toStdString();
}

TEST(ViewerLoading, CancelLeavesTheSceneUnchanged) {
  Application();
  const fs::path series = LargeSeries();
  vtkNew<vtkRPScene> scene;
  qRPViewerMainWindow window(nullptr, scene);
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

TEST(ViewerLoading, ASceneFileIsHandedBackToTheGuiThreadAndOpens) {
  Application();
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "scene-file";
  fs::create_directories(dir);
  const std::string path = (dir / "plan.rpscene").string();
  {
    vtkNew<vtkRPScene> source;
    vtkNew<vtkImageData> image;
    image->SetDimensions(8, 6, 4);
    image->AllocateScalars(VTK_SHORT, 1);
    short* v = static_cast<short*>(image->GetScalarPointer());
    for (int n = 0; n < 8 * 6 * 4; ++n) v[n] = static_cast<short>(n);
    vtkNew<vtkRPScalarVolumeNode> volume;
    volume->SetName("small CT");
    volume->SetImageData(image);
    source->AddNode(volume);
    std::string error;
    ASSERT_TRUE(rp::SaveScene(source, path, error)) << error;
  }
  vtkNew<vtkRPScene> scene;
  qRPViewerMainWindow window(nullptr, scene);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  QString error;
  ASSERT_TRUE(window.LoadFile(QString::fromStdString(path), &error)) << error.toStdString();
  const auto volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
  ASSERT_EQ(volumes.size(), 1u);
  EXPECT_EQ(volumes[0]->GetName(), "small CT");
  vtkImageData* loaded = vtkRPScalarVolumeNode::SafeDownCast(volumes[0])->GetImageData();
  ASSERT_NE(loaded, nullptr);
  int dims[3];
  loaded->GetDimensions(dims);
  EXPECT_EQ(dims[0], 8);
  EXPECT_EQ(dims[1], 6);
  EXPECT_EQ(dims[2], 4);
  EXPECT_EQ(loaded->GetScalarComponentAsDouble(7, 5, 3, 0), 8 * 6 * 4 - 1);
}

// File > Load DICOM folder goes through the one loader: the scan's choices (the whole folder
// first, then each series as `roboplan dicom` lists it), one series by its ID, and the whole
// folder, each the same nodes as rp::LoadPath gives (names, geometry, voxel values).
TEST(ViewerLoading, DicomFolderMenuLoadsThroughTheLoader) {
  Application();
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "dicom-two-series";
  fs::remove_all(dir);
  std::string error;
  for (int s = 0; s < 2; ++s) {  // a CT of 10 and an MR of 6 slices, 2 mm apart, values by series
    rp::ImageVolume volume;
    volume.Image = vtkSmartPointer<vtkImageData>::New();
    volume.Image->SetDimensions(16, 12, s == 0 ? 10 : 6);
    volume.Image->AllocateScalars(VTK_SHORT, 1);
    short* v = static_cast<short*>(volume.Image->GetScalarPointer());
    for (vtkIdType i = 0; i < volume.Image->GetNumberOfPoints(); ++i) v[i] = static_cast<short>(100 * (s + 1) + i % 7);
    volume.IJKToRAS->SetElement(2, 2, 2.0);
    rp::DicomWriteOptions options;
    options.Modality = s == 0 ? "CT" : "MR";
    options.SeriesDescription = s == 0 ? "knee CT" : "knee MR";
    options.SeriesNumber = s + 1;
    options.FilePrefix = s == 0 ? "CT" : "MR";
    ASSERT_TRUE(rp::WriteDicomSeries(volume, dir.string(), options, error)) << error;
  }
  vtkNew<vtkRPScene> scene;
  qRPViewerMainWindow window(nullptr, scene);
  const QString folder = QString::fromStdString(dir.string());

  QString message;
  const auto choices = window.DicomFolderChoices(folder, &message);
  ASSERT_EQ(choices.size(), 3u) << message.toStdString();
  EXPECT_TRUE(choices[0].second.isEmpty());
  EXPECT_TRUE(choices[0].first.contains("2 image stacks")) << choices[0].first.toStdString();
  const auto mr = std::find_if(choices.begin(), choices.end(), [](const auto& c) { return c.first.startsWith("MR 2"); });
  ASSERT_NE(mr, choices.end());
  EXPECT_TRUE(mr->first.contains("16x12x6")) << mr->first.toStdString();

  // One series: the MR alone, as the loader reads it by that ID.
  ASSERT_TRUE(window.LoadFile(folder, &message, mr->second)) << message.toStdString();
  auto volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
  ASSERT_EQ(volumes.size(), 1u);
  auto* node = vtkRPScalarVolumeNode::SafeDownCast(volumes.front());
  EXPECT_EQ(node->GetName(), "knee MR");
  int dims[3];
  node->GetImageData()->GetDimensions(dims);
  EXPECT_EQ(dims[2], 6);
  EXPECT_EQ(node->GetImageData()->GetScalarComponentAsDouble(3, 0, 0, 0), 203.0);  // 100 * 2 + 3 % 7
  vtkNew<vtkRPScene> byLoader;
  rp::ReadOptions options;
  options.Series = mr->second.toStdString();
  const rp::LoadResult direct = rp::LoadPath(byLoader, dir.string(), options);
  ASSERT_TRUE(direct.Ok) << direct.Error;
  auto* same = vtkRPScalarVolumeNode::SafeDownCast(byLoader->GetNodesByClass("vtkRPScalarVolumeNode").front());
  EXPECT_EQ(same->GetName(), node->GetName());
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_DOUBLE_EQ(same->GetIJKToRASMatrix()->GetElement(r, c), node->GetIJKToRASMatrix()->GetElement(r, c));

  // The whole folder: both series beside the MR already there (nothing lost).
  ASSERT_TRUE(window.LoadFile(folder, &message, QString())) << message.toStdString();
  volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
  ASSERT_EQ(volumes.size(), 3u);
  std::set<std::string> names;
  for (auto* v : volumes) names.insert(v->GetName());
  EXPECT_EQ(names, (std::set<std::string>{"knee CT", "knee MR", "knee MR_1"}));  // the scene keeps names unique

  // An ID the folder does not hold is named in the error; the scene keeps its three volumes.
  EXPECT_FALSE(window.LoadFile(folder, &message, "1.2.3.4.5"));
  EXPECT_TRUE(message.contains("1.2.3.4.5")) << message.toStdString();
  EXPECT_EQ(scene->GetNodesByClass("vtkRPScalarVolumeNode").size(), 3u);

  // A folder with nothing DICOM in it gives no choices and says so.
  const fs::path empty = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "dicom-none";
  fs::create_directories(empty);
  std::ofstream(empty / "notes.txt") << "not DICOM\n";
  EXPECT_TRUE(window.DicomFolderChoices(QString::fromStdString(empty.string()), &message).empty());
  EXPECT_FALSE(message.isEmpty());
}
