// The Navigation panel's score (issue 38) on known answers: a CSV of tip points along a line offset
// from the plan by a known vector d (normal to the plan) and tilted by a known angle θ towards a
// direction u normal to the plan and to d gives entry offset |d|, tip offset √(|d|² + (L tan θ)²),
// angle θ (closed form, 1e-6 relative); PLUS's real stylus recording (../shared/oracles/plus-data)
// scored through the panel, its transform chosen from the combo the file filled, saves the JSON
// `roboplan score --json` prints for the same plan and path; bad input is named and leaves the
// scene as it was. The score runs on a worker thread: the panel waits in its event loop.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QImage>
#include <QLabel>
#include <QLineEdit>
#include <QPixmap>
#include <QProgressBar>
#include <QPushButton>
#include <QTableWidget>
#include <QTimer>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "qRPNavigationPanel.h"
#include "qRPScorePanel.h"
#include "rpBenchmarkChart.h"
#include "rpNodeStorage.h"
#include "rpScoreCommand.h"
#include "rpScoredExecution.h"
#include "rpSharedData.h"
#include "rpTestOutput.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"

namespace {

const std::string PlusData = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data";

QApplication& App() {
  static int argc = 1;
  static char name[] = "qRPScorePanelTest";
  static char* argv[] = {name};
  static QApplication app(argc, argv);
  return app;
}

// Scores what the panel's widgets say and waits for the worker (a few seconds at most).
void ScoreAndWait(qRPScorePanel& panel) {
  if (!panel.StartScore()) return;
  EXPECT_TRUE(panel.IsScoring());
  EXPECT_FALSE(panel.ScoreButton->isEnabled()) << "one score at a time";
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (panel.IsScoring() && std::chrono::steady_clock::now() < end) App().processEvents(QEventLoop::AllEvents, 10);
  ASSERT_FALSE(panel.IsScoring());
  EXPECT_TRUE(panel.ScoreButton->isEnabled());
}

struct PlannedScene {
  vtkNew<vtkRPScene> Scene;
  vtkNew<vtkRPNavigationLogic> Logic;
  vtkNew<vtkRPTrajectoryNode> Trajectory;
  PlannedScene(const double entry[3], const double target[3], double diameter) {
    this->Trajectory->SetName("tunnel");
    this->Trajectory->SetEntryAndTarget(entry, target);
    this->Trajectory->SetToolDiameterMm(diameter);
    this->Scene->AddNode(this->Trajectory);
    this->Logic->SetScene(this->Scene);
  }
};

std::string WriteText(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file.string();
}

// Tip points from entry + d along the plan's −S tilted by θ towards u, `run` mm long.
std::string LinePath(const double entry[3], const double d[3], const double u[3], double theta, double run) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "R,A,S\n";
  for (double s = 0; s <= run + 1e-9; s += 0.25)
    csv << entry[0] + d[0] + s * std::sin(theta) * u[0] << "," << entry[1] + d[1] + s * std::sin(theta) * u[1] << ","
        << entry[2] + d[2] - s * std::cos(theta) << "\n";
  return csv.str();
}

bool HasColor(const QImage& image, const std::array<unsigned char, 3>& rgb) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb p = image.pixel(x, y);
      if (std::abs(qRed(p) - rgb[0]) < 8 && std::abs(qGreen(p) - rgb[1]) < 8 && std::abs(qBlue(p) - rgb[2]) < 8) return true;
    }
  return false;
}

TEST(ScorePanel, AnOffsetAndTiltedLineGivesTheClosedFormsInTheTableAndTheChart) {
  App();
  const auto dir = rptest::TestDir("closed-form");
  const double length = 40, theta = 3 * M_PI / 180, run = 42;
  const double entry[3] = {10, 20, 30}, target[3] = {10, 20, 30 - length};
  const double d[3] = {0.9, 1.2, 0}, u[3] = {0.8, -0.6, 0};  // |d| = 1.5, u ⟂ d, both ⟂ the plan
  PlannedScene s(entry, target, 3);
  qRPNavigationPanel navigation(s.Logic);
  qRPScorePanel& panel = *navigation.ScorePanel();
  EXPECT_EQ(panel.TrajectoryCombo->currentText(), "tunnel") << "the scene's trajectory is offered";
  panel.PathEdit->setText(QString::fromStdString(WriteText(dir / "tilted.csv", LinePath(entry, d, u, theta, run))));
  ScoreAndWait(panel);
  ASSERT_NE(panel.LastScore(), nullptr) << panel.StatusText().toStdString();
  EXPECT_FALSE(panel.IsErrorShown());
  const double tipLateral = length * std::tan(theta);
  auto near = [](double value, double expected) { return std::fabs(value - expected) <= 1e-6 * std::fabs(expected); };
  EXPECT_TRUE(near(panel.FigureValue(qRPScorePanel::EntryOffset), 1.5)) << panel.FigureValue(qRPScorePanel::EntryOffset);
  EXPECT_TRUE(near(panel.FigureValue(qRPScorePanel::TipOffset), std::hypot(1.5, tipLateral)));
  EXPECT_TRUE(near(panel.FigureValue(qRPScorePanel::Angle), 3));
  EXPECT_TRUE(near(panel.FigureValue(qRPScorePanel::DepthError), run * std::cos(theta) - length));
  EXPECT_TRUE(near(panel.FigureValue(qRPScorePanel::MaxDeviation), std::hypot(1.5, run * std::sin(theta))));
  EXPECT_EQ(panel.FigureText(qRPScorePanel::EntryOffset), "1.500 mm");
  EXPECT_EQ(panel.FigureText(qRPScorePanel::Angle), QString::fromUtf8("3.000°"));
  EXPECT_EQ(panel.FigureText(qRPScorePanel::Breach), "no bone chosen");
  EXPECT_EQ(panel.FigureText(panel.FigureRow("Outside the plan's cylinder")), "no tool radius (a tip sweeps no volume)");
  EXPECT_TRUE(panel.SaveButton->isEnabled());
  // The chart of the deviation along depth, as `roboplan score --chart` draws it (its series colour).
  const QPixmap chart = panel.ChartLabel->pixmap(Qt::ReturnByValue);
  ASSERT_FALSE(chart.isNull()) << panel.ChartLabel->text().toStdString();
  EXPECT_TRUE(HasColor(chart.toImage(), rp::bench::SeriesColor(0)));
  chart.save(QString::fromStdString((dir / "deviation-along-depth.png").string()));
  panel.resize(520, 900);
  panel.grab().save(QString::fromStdString((dir / "score-panel.png").string()));  // to look at

  // With a tool radius the swept volume outside the plan's cylinder is measured. The window stays
  // live while it scores: an event posted after "Score" is handled before the score ends.
  panel.ToolRadiusSpin->setValue(1.5);
  bool liveWhileScoring = false;
  QTimer::singleShot(0, &panel, [&] { liveWhileScoring = panel.IsScoring() && panel.ScoreProgress->isVisibleTo(&panel); });
  ScoreAndWait(panel);
  EXPECT_TRUE(liveWhileScoring);
  EXPECT_FALSE(panel.ScoreProgress->isVisibleTo(&panel));
  ASSERT_NE(panel.LastScore(), nullptr);
  EXPECT_GT(panel.FigureValue(panel.FigureRow("Outside the plan's cylinder")), 0);
}

TEST(ScorePanel, PlusRecordingScoredThroughThePanelEqualsTheCommandsJson) {
  App();
  RP_REQUIRE_SHARED_DATA(PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha");
  const auto dir = rptest::TestDir("plus");
  const std::string sequence = PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha";
  const std::string config = PlusData + "/ConfigFiles/PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml";
  // The plan in Reference coordinates, as rpGuidanceTest's: from the stylus's third rest to its fifth.
  const double entry[3] = {2, 3, 130}, target[3] = {8, 6, -8};
  PlannedScene s(entry, target, 2);
  qRPScorePanel panel(s.Logic);
  panel.PathEdit->setText(QString::fromStdString(sequence));
  panel.RefreshTransforms();
  EXPECT_EQ(panel.TransformCombo->findText("StylusTipToReference"), -1) << "not without the configuration's calibration";
  EXPECT_GE(panel.TransformCombo->findText("StylusToReference"), 0);
  panel.ConfigurationEdit->setText(QString::fromStdString(config));
  panel.RefreshTransforms();
  const int tip = panel.TransformCombo->findText("StylusTipToReference");
  ASSERT_GE(tip, 0);
  EXPECT_TRUE(panel.TransformCombo->itemText(0).contains("Tip")) << "tool tips first";
  panel.TransformCombo->setCurrentIndex(tip);
  ScoreAndWait(panel);
  ASSERT_NE(panel.LastScore(), nullptr) << panel.StatusText().toStdString();
  const std::string saved = (dir / "score.json").string();
  QString error;
  ASSERT_TRUE(panel.SaveScore(QString::fromStdString(saved), error)) << error.toStdString();

  const std::string plan = (dir / "tunnel.mrk.json").string();  // loads as a node named after the file
  std::string why;
  const rp::NodeStorage* storage = rp::FindNodeStorageForFile(plan);
  ASSERT_TRUE(storage && storage->Write(s.Trajectory, plan, why)) << why;
  std::ostringstream out, err;
  ASSERT_EQ(rp::RunScoreCommand({"--plan", plan, "--path", sequence, "--transform", "StylusTipToReference",
                                 "--configuration", config, "--json"},
                                out, err),
            0)
      << err.str();
  nlohmann::json command = nlohmann::json::parse(out.str()), shown = nlohmann::json::parse(std::ifstream(saved));
  EXPECT_EQ(shown["plan"]["file"], "") << "the panel's plan is the scene";
  command["plan"].erase("file");
  shown["plan"].erase("file");
  EXPECT_EQ(shown, command) << "the panel and the command run the same score";
  EXPECT_NEAR(panel.FigureValue(qRPScorePanel::EntryOffset), command["entryOffsetMm"].get<double>(), 1e-12);
}

TEST(ScorePanel, BadInputIsNamedAndTheSceneIsKept) {
  App();
  const auto dir = rptest::TestDir("bad");
  const double entry[3] = {10, 20, 30}, target[3] = {10, 20, -10};
  PlannedScene s(entry, target, 3);
  const int nodes = s.Scene->GetNumberOfNodes();
  qRPScorePanel panel(s.Logic);
  auto expectError = [&](const std::string& contains) {
    ScoreAndWait(panel);
    EXPECT_TRUE(panel.IsErrorShown()) << panel.StatusText().toStdString();
    EXPECT_NE(panel.StatusText().toStdString().find(contains), std::string::npos) << panel.StatusText().toStdString();
    EXPECT_EQ(panel.LastScore(), nullptr);
    EXPECT_EQ(panel.FiguresTable->rowCount(), 0);
    EXPECT_FALSE(panel.SaveButton->isEnabled());
  };
  expectError("choose the executed path");
  panel.PathEdit->setText(QString::fromStdString((dir / "missing.csv").string()));
  expectError("cannot open the path '" + (dir / "missing.csv").string() + "'");
  panel.PathEdit->setText(QString::fromStdString(WriteText(dir / "one.csv", "R,A,S\n10,20,25\n")));
  expectError("fewer than two distinct points");
  panel.PathEdit->setText(QString::fromStdString(WriteText(dir / "bad-row.csv", "R,A,S\n10,20,25\n10,20\n")));
  expectError("bad-row.csv:3:");
  if (std::filesystem::exists(PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha")) {
    panel.PathEdit->setText(
        QString::fromStdString(PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha"));
    panel.RefreshTransforms();
    panel.TransformCombo->setEditText("NeedleTipToReference");  // typed: no such tool in the file
    ScoreAndWait(panel);
    EXPECT_TRUE(panel.IsErrorShown());
    EXPECT_NE(panel.StatusText().toStdString().find("NeedleTipToReference cannot be computed from its transforms"),
              std::string::npos)
        << panel.StatusText().toStdString();
  }
  // A path in another frame (200 mm off): scored, with a warning that names the likely cause.
  const double d[3] = {200, 0, 0}, u[3] = {0, 1, 0};
  panel.PathEdit->setText(QString::fromStdString(WriteText(dir / "far.csv", LinePath(entry, d, u, 0.01, 30))));
  ScoreAndWait(panel);
  ASSERT_NE(panel.LastScore(), nullptr) << panel.StatusText().toStdString();
  EXPECT_FALSE(panel.IsErrorShown());
  EXPECT_NE(panel.StatusText().toStdString().find("never comes within 50 mm of the trajectory 'tunnel'"), std::string::npos)
      << panel.StatusText().toStdString();
  // No trajectory left in the scene: named before anything runs.
  s.Scene->RemoveNode(s.Trajectory);
  panel.RefreshNodeLists();
  EXPECT_FALSE(panel.StartScore());
  EXPECT_NE(panel.StatusText().toStdString().find("choose a planned trajectory"), std::string::npos);
  s.Scene->AddNode(s.Trajectory);
  EXPECT_EQ(s.Scene->GetNumberOfNodes(), nodes) << "scoring added or removed nothing";
  double kept[3];
  ASSERT_TRUE(s.Trajectory->GetEntryWorld(kept));
  EXPECT_EQ(kept[2], 30);

  // A panel closed while it scores waits for its worker and drops the result.
  auto closing = std::make_unique<qRPScorePanel>(s.Logic);
  closing->PathEdit->setText(QString::fromStdString((dir / "far.csv").string()));
  closing->ToolRadiusSpin->setValue(2);
  ASSERT_TRUE(closing->StartScore());
  closing.reset();
  App().processEvents();
}

}  // namespace
