#include "qRPScorePanel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <QFileDialog>
#include <QFileInfo>
#include <QHeaderView>
#include <QPixmap>
#include <QSignalBlocker>
#include <QTableWidgetItem>
#include <QTemporaryDir>
#include <QThread>

#include "rpExecutionPath.h"
#include "rpScoredExecution.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace {
QString Text(const std::string& text) { return QString::fromStdString(text); }
const double NoValue = std::numeric_limits<double>::quiet_NaN();
}  // namespace

qRPScorePanel::qRPScorePanel(vtkRPNavigationLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  this->ScoreProgress->setVisible(false);
  connect(this->ScoreButton, &QPushButton::clicked, this, [this] { this->StartScore(); });
  connect(this->SaveButton, &QPushButton::clicked, this, &qRPScorePanel::OnSave);
  connect(this->PathBrowseButton, &QToolButton::clicked, this, &qRPScorePanel::BrowsePath);
  connect(this->ConfigurationBrowseButton, &QToolButton::clicked, this, &qRPScorePanel::BrowseConfiguration);
  connect(this->PathEdit, &QLineEdit::editingFinished, this, &qRPScorePanel::RefreshTransforms);
  connect(this->ConfigurationEdit, &QLineEdit::editingFinished, this, &qRPScorePanel::RefreshTransforms);
  this->RefreshNodeLists();
  this->RefreshTransforms();
}

qRPScorePanel::~qRPScorePanel() {
  if (this->Worker) {  // a score still running: let it end (it touches no scene node), drop its result
    this->Worker->disconnect(this);
    this->Worker->wait();
    delete this->Worker;
  }
}

void qRPScorePanel::RefreshNodeLists() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (!scene) return;
  auto fill = [scene](QComboBox* combo, const char* className, const QString& none) {
    const QString current = combo->currentData().toString();
    const QSignalBlocker block(combo);
    combo->clear();
    if (!none.isEmpty()) combo->addItem(none, QString());
    for (vtkRPNode* node : scene->GetNodesByClass(className)) combo->addItem(Text(node->GetName()), Text(node->GetID()));
    combo->setCurrentIndex(std::max(0, combo->findData(current)));
  };
  fill(this->TrajectoryCombo, "vtkRPTrajectoryNode", QString());
  fill(this->BoneCombo, "vtkRPModelNode", "(none)");
}

void qRPScorePanel::RefreshTransforms() {
  const QString current = this->TransformCombo->currentText();
  std::vector<std::string> names;
  std::string error;
  const std::string path = this->PathEdit->text().trimmed().toStdString();
  const bool listed = path.empty() || rp::ListPathTransforms(path, this->ConfigurationEdit->text().trimmed().toStdString(),
                                                             names, error);
  this->TransformCombo->clear();
  for (const std::string& name : names) this->TransformCombo->addItem(Text(name));
  this->TransformCombo->setEnabled(!names.empty() || !listed);
  const int index = this->TransformCombo->findText(current);
  if (index >= 0) {
    this->TransformCombo->setCurrentIndex(index);
  } else if (names.empty()) {
    this->TransformCombo->setEditText(listed ? QString() : current);
  }
  if (!listed) this->ShowStatus(Text(error), true);
}

bool qRPScorePanel::StartScore() {
  if (this->Worker || !this->Logic) return false;
  rp::ScoreRequest request;
  request.Trajectory = this->TrajectoryCombo->currentData().toString().toStdString();
  request.PathFile = this->PathEdit->text().trimmed().toStdString();
  if (request.Trajectory.empty()) {
    this->ShowStatus("choose a planned trajectory (the scene has none)", true);
    return false;
  }
  if (request.PathFile.empty()) {
    this->ShowStatus("choose the executed path: a drilling recording, a PLUS sequence (.igs.mha) or a CSV R,A,S", true);
    return false;
  }
  request.PathOptions.Transform = this->TransformCombo->currentText().trimmed().toStdString();
  request.PathOptions.Configuration = this->ConfigurationEdit->text().trimmed().toStdString();
  request.BoneModelNodeID = this->BoneCombo->currentData().toString().toStdString();
  request.ToolRadiusMm = this->ToolRadiusSpin->value() < 0 ? -1 : this->ToolRadiusSpin->value();
  auto job = std::make_unique<rp::ScoredExecution>();
  std::string error;
  if (!this->Logic->PrepareScore(request, *job, error)) {  // the scene's part, here on the GUI thread
    this->ShowStatus(Text(error), true);
    return false;
  }
  this->Running = std::move(job);
  this->RunningOk = false;
  this->RunningError.clear();
  rp::ScoredExecution* running = this->Running.get();
  this->Worker = QThread::create([this, running] { this->RunningOk = rp::RunScore(*running, this->RunningError); });
  connect(this->Worker, &QThread::finished, this, &qRPScorePanel::OnScored);
  this->ScoreButton->setEnabled(false);
  this->ScoreProgress->setVisible(true);
  this->ShowStatus("scoring " + QFileInfo(Text(request.PathFile)).fileName() + "…", false);
  this->Worker->start();
  return true;
}

void qRPScorePanel::OnScored() {
  this->Worker->wait();
  delete this->Worker;
  this->Worker = nullptr;
  this->ScoreProgress->setVisible(false);
  this->ScoreButton->setEnabled(true);
  if (!this->RunningOk) {
    this->Running.reset();
    this->Scored.reset();
    this->FiguresTable->setRowCount(0);
    this->ChartLabel->clear();
    this->SaveButton->setEnabled(false);
    this->ShowStatus(Text(this->RunningError), true);
    return;
  }
  this->Scored = std::move(this->Running);
  this->ShowFigures();
  this->ShowChart();
  this->SaveButton->setEnabled(true);
  const rp::ExecutionPath& path = this->Scored->Path;
  QString status = QString("%1: %2 points of %3 against '%4'")
                       .arg(Text(path.Kind))
                       .arg(path.Points.size())
                       .arg(path.Samples)
                       .arg(Text(this->Scored->Trajectory.Name));
  for (const std::string& warning : this->Scored->Warnings) status += "\nwarning: " + Text(warning);
  this->ShowStatus(status, false);
}

void qRPScorePanel::AddFigure(const QString& name, const QString& text, double value, bool warn) {
  const int row = this->FiguresTable->rowCount();
  this->FiguresTable->insertRow(row);
  this->FiguresTable->setItem(row, 0, new QTableWidgetItem(name));
  auto* item = new QTableWidgetItem(text);
  item->setData(Qt::UserRole, value);
  if (warn) item->setForeground(QColor(220, 30, 30));
  this->FiguresTable->setItem(row, 1, item);
}

void qRPScorePanel::ShowFigures() {
  const rp::ExecutionScore& s = this->Scored->Score;
  this->FiguresTable->setRowCount(0);
  auto mm = [](double v, const char* format = "%1 mm") { return QString(format).arg(v, 0, 'f', 3); };
  this->AddFigure("Entry offset", mm(s.EntryOffsetMm), s.EntryOffsetMm);
  this->AddFigure("Tip offset", mm(s.TipOffsetMm), s.TipOffsetMm);
  this->AddFigure("Angle", QString::fromUtf8("%1°").arg(s.AngleDeg, 0, 'f', 3), s.AngleDeg);
  this->AddFigure("Depth error", QString("%1%2 mm").arg(s.DepthErrorMm >= 0 ? "+" : "").arg(s.DepthErrorMm, 0, 'f', 3),
                  s.DepthErrorMm);
  this->AddFigure("Largest deviation", mm(s.MaxDeviationMm), s.MaxDeviationMm);
  if (s.HasBreach) {
    this->AddFigure("Breach", QString("%1 mm (Gertzbein-Robbins grade %2)").arg(s.BreachMm, 0, 'f', 2).arg(s.BreachGrade),
                    s.BreachMm, s.BreachGrade > 0);
  } else {
    this->AddFigure("Breach", "no bone chosen", NoValue);
  }
  for (const rp::StructureClearance& c : s.Clearance)
    this->AddFigure("Closest to " + Text(c.Name),
                    QString("%1 mm (margin %2 mm)%3")
                        .arg(c.ClosestMm, 0, 'f', 2)
                        .arg(c.MarginMm, 0, 'f', 2)
                        .arg(c.WithinMargin ? ", within the margin" : ""),
                    c.ClosestMm, c.WithinMargin);
  if (s.HasVolume) {
    this->AddFigure("Outside the plan's cylinder",
                    QString::fromUtf8("%1 mm³ (of %2 mm³ swept)").arg(s.OutsideVolumeMm3, 0, 'f', 1).arg(s.DrilledVolumeMm3, 0, 'f', 1),
                    s.OutsideVolumeMm3);
  } else {
    this->AddFigure("Outside the plan's cylinder", "no tool radius (a tip sweeps no volume)", NoValue);
  }
  this->FiguresTable->resizeColumnToContents(0);
  // Every figure visible at once: the table as tall as its rows.
  int height = this->FiguresTable->horizontalHeader()->height() + 2 * this->FiguresTable->frameWidth();
  for (int row = 0; row < this->FiguresTable->rowCount(); ++row) height += this->FiguresTable->rowHeight(row);
  this->FiguresTable->setMinimumHeight(height);
}

void qRPScorePanel::ShowChart() {
  if (!this->ChartDir) this->ChartDir = std::make_unique<QTemporaryDir>();
  const QString file = this->ChartDir->filePath("deviation-along-depth.png");
  std::string error;
  QPixmap chart;
  if (!this->ChartDir->isValid() || !rp::WriteDeviationChart(this->Scored->Score, file.toStdString(), error, 480, 320) ||
      !chart.load(file)) {
    this->ChartLabel->setText("the chart was not drawn: " + (error.empty() ? file : Text(error)));
    return;
  }
  this->ChartLabel->setPixmap(chart);
}

void qRPScorePanel::ShowStatus(const QString& text, bool error) {
  this->ErrorShown = error;
  this->StatusLabel->setText(text);
  this->StatusLabel->setStyleSheet(error ? "color: rgb(220, 30, 30);" : "");
}

QString qRPScorePanel::StatusText() const { return this->StatusLabel->text(); }

int qRPScorePanel::FigureRow(const QString& name) const {
  for (int row = 0; row < this->FiguresTable->rowCount(); ++row)
    if (this->FiguresTable->item(row, 0)->text() == name) return row;
  return -1;
}

QString qRPScorePanel::FigureText(int row) const {
  const QTableWidgetItem* item = this->FiguresTable->item(row, 1);
  return item ? item->text() : QString();
}

double qRPScorePanel::FigureValue(int row) const {
  const QTableWidgetItem* item = this->FiguresTable->item(row, 1);
  return item ? item->data(Qt::UserRole).toDouble() : NoValue;
}

bool qRPScorePanel::SaveScore(const QString& file, QString& error) const {
  if (!this->Scored) {
    error = "nothing scored yet";
    return false;
  }
  std::string why;
  // The plan is the viewer's scene, not a file: `plan.file` is empty.
  if (rp::WriteScoredExecutionJson(*this->Scored, "", file.toStdString(), why)) return true;
  error = Text(why);
  return false;
}

void qRPScorePanel::BrowsePath() {
  const QString file = QFileDialog::getOpenFileName(
      this, "Executed path", this->PathEdit->text(),
      "Executed paths (*.csv *.mha *.mhd *.nrrd *.txt);;CSV R,A,S (*.csv);;PLUS sequences (*.mha *.mhd *.nrrd);;All files (*)");
  if (file.isEmpty()) return;
  this->PathEdit->setText(file);
  this->RefreshTransforms();
}

void qRPScorePanel::BrowseConfiguration() {
  const QString file = QFileDialog::getOpenFileName(this, "PLUS configuration", this->ConfigurationEdit->text(),
                                                    "PLUS configurations (*.xml);;All files (*)");
  if (file.isEmpty()) return;
  this->ConfigurationEdit->setText(file);
  this->RefreshTransforms();
}

void qRPScorePanel::OnSave() {
  const QString file = QFileDialog::getSaveFileName(this, "Save score", "score.json", "JSON (*.json)");
  if (file.isEmpty()) return;
  QString error;
  if (!this->SaveScore(file, error)) {
    this->ShowStatus(error, true);
    return;
  }
  this->ShowStatus("saved " + file, false);
}
