#ifndef qRPScorePanel_h
#define qRPScorePanel_h
// An execution scored against its plan, in the viewer (issue 38; the layout is qRPScorePanel.ui,
// a group of the Navigation panel): choose a trajectory of the scene, the executed path (a drilling
// recording, a PLUS sequence with the transform to follow, filled from the file, and optionally
// its PLUS configuration, or a CSV R,A,S), optionally the drilled bone and the tool's radius;
// "Score" runs vtkRPNavigationLogic's score (the one `roboplan score` runs): the scene's part on
// the GUI thread (PrepareScore), reading and scoring on a worker thread (rp::RunScore) while a busy
// bar shows, so a long recording never freezes the window. The figures go into a table, the
// deviation along depth into the chart `roboplan score --chart` draws; "Save score…" writes the
// command's JSON. Bad input is named in red; the scene is never touched.
#include <QWidget>

#include <memory>
#include <string>

#include "ui_qRPScorePanel.h"

class QThread;
class QTemporaryDir;
class vtkRPNavigationLogic;
namespace rp {
struct ScoredExecution;
}

/// The widgets (Ui::qRPScorePanel: TrajectoryCombo, PathEdit, TransformCombo, ConfigurationEdit,
/// BoneCombo, ToolRadiusSpin, ScoreButton, SaveButton, StatusLabel, FiguresTable, ChartLabel) are
/// public members, for tests and scripting.
class qRPScorePanel : public QWidget, public Ui::qRPScorePanel {
  Q_OBJECT
 public:
  /// The figures table's rows, in order (structures at risk follow Breach, one row each).
  enum Row { EntryOffset = 0, TipOffset, Angle, DepthError, MaxDeviation, Breach };

  explicit qRPScorePanel(vtkRPNavigationLogic* logic, QWidget* parent = nullptr);
  ~qRPScorePanel() override;

  /// Re-reads the scene's trajectories and models into the combos (keeps the choices).
  void RefreshNodeLists();
  /// Fills the transform combo from the path file (PLUS sequences; empty otherwise).
  void RefreshTransforms();
  /// Starts scoring (what "Score" does). False, with the reason in the status line, when the
  /// score could not start (no trajectory, a bone without a surface, ...).
  bool StartScore();
  bool IsScoring() const { return this->Worker != nullptr; }
  /// The last score shown (null before one, or after a score that failed).
  const rp::ScoredExecution* LastScore() const { return this->Scored.get(); }
  /// The status line: the last error (red), warning or summary.
  QString StatusText() const;
  bool IsErrorShown() const { return this->ErrorShown; }
  /// The row of a figure by its name ("Entry offset", "Closest to vessel", ...; -1 when absent).
  int FigureRow(const QString& name) const;
  /// The figure of a row as shown and its full value (Qt::UserRole of the value's item).
  QString FigureText(int row) const;
  double FigureValue(int row) const;
  /// Writes the last score as `roboplan score --json` prints it (what "Save score…" does).
  bool SaveScore(const QString& file, QString& error) const;

 private:
  void OnScored();
  void ShowFigures();
  void ShowChart();
  void ShowStatus(const QString& text, bool error);
  void AddFigure(const QString& name, const QString& text, double value, bool warn = false);
  void BrowsePath();
  void BrowseConfiguration();
  void OnSave();

  vtkRPNavigationLogic* Logic;
  QThread* Worker = nullptr;                       // the running score (null when idle)
  std::unique_ptr<rp::ScoredExecution> Running;    // written by the worker until it finishes
  std::string RunningError;
  bool RunningOk = false;
  std::unique_ptr<rp::ScoredExecution> Scored;     // the score shown
  std::unique_ptr<QTemporaryDir> ChartDir;         // the chart's PNG, drawn by Libs/Charts
  bool ErrorShown = false;
};

#endif
