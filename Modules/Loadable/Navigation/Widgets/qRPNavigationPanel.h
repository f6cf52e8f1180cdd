#ifndef qRPNavigationPanel_h
#define qRPNavigationPanel_h
// The Navigation module's Qt panel: pick the tool (a transform node whose origin is the tip,
// e.g. StylusTipToStylus or HapticProxy), tick the models to measure to and a warning distance;
// shows the tip-to-surface distance big, red under the warning distance, green otherwise, with
// the closest model's name; the slices can follow the tool (through the scene's slice nodes);
// with a planned trajectory chosen, the tool's read-out against it (entry error, angle, depth to
// target, lateral distance; issue 38). vtkRPNavigationLogic does the work (and writes Navigation.*
// attributes onto the tool node for the viewer); a 30 Hz timer refreshes the read-outs. Below
// them, the target ("bull's-eye") view and the chosen volume re-sliced along and across the plan
// at the tool tip (rpTargetView.h), drawn when the read-out changed; and a check box that streams
// the read-outs over OpenIGTLink (vtkRPNavigationLogic::StartReadoutServer). Last, an execution
// scored against its plan (qRPScorePanel: the trajectory chosen above is its default). The layout
// is qRPNavigationPanel.ui.
#include <QImage>
#include <QWidget>

#include <memory>
#include <vector>

#include "ui_qRPNavigationPanel.h"

class QTimer;
namespace rp {
class SceneNodesWatch;
class TargetViewPicture;
}
class qRPScorePanel;
class vtkRPNavigationLogic;

/// The widgets (Ui::qRPNavigationPanel) are private: the accessors below are the panel's interface.
class qRPNavigationPanel : public QWidget, private Ui::qRPNavigationPanel {
  Q_OBJECT
 public:
  explicit qRPNavigationPanel(vtkRPNavigationLogic* logic, QWidget* parent = nullptr);
  ~qRPNavigationPanel() override;

  /// Re-reads the scene's transform and model nodes into the combo and the list (keeps choices).
  void RefreshNodeLists();
  /// Pushes the widgets' choices into the logic, recomputes and updates the read-out.
  void Update();

  QComboBox* ToolComboBox() const { return this->Tool; }
  QListWidget* ModelList() const { return this->Models; }
  QDoubleSpinBox* WarningSpinBox() const { return this->Warning; }
  /// The planned trajectory the tool is read out against ("(none)" first).
  QComboBox* TrajectoryComboBox() const { return this->Trajectory; }
  /// "entry 1.2 mm · angle 2.5° · depth to target 10.2 mm · lateral 0.8 mm", or "-".
  QString ReadoutText() const;
  /// "closest structure at risk: vessel 3.2 mm (margin 2.0 mm)", or "-"; red under its margin.
  QString StructureText() const;
  bool IsStructureWarningShown() const { return this->StructureWarningShown; }
  /// The volume the re-sliced views show ("(none)" first).
  QComboBox* VolumeComboBox() const { return this->Volume; }
  /// The target view and the re-sliced views as last drawn (null before a read-out), and the
  /// picture shown (empty when none).
  const rp::TargetViewPicture* TargetView() const { return this->Picture.get(); }
  QImage TargetViewImage() const;
  /// "Stream read-outs over OpenIGTLink" on the port beside it (127.0.0.1), and its state line.
  QCheckBox* StreamCheckBox() const { return this->Stream; }
  QSpinBox* StreamPortSpinBox() const { return this->StreamPort; }
  QString StreamText() const;
  /// "Slices follow the tool": the scene's slice nodes follow the chosen tool's tip (the views
  /// re-slice at the tracked stylus; the panel never touches a view).
  qRPSliceFollowCheckBox* FollowToolCheckBox() const { return this->FollowTool; }
  /// "Score an execution against its plan" (qRPScorePanel.h), below the views.
  qRPScorePanel* ScorePanel() const { return this->Score; }
  QString DistanceText() const;
  QString ClosestModelText() const;
  /// True when the distance is shown in the warning colour.
  bool IsWarningShown() const { return this->WarningShown; }

 protected:
  void showEvent(QShowEvent* event) override;

 private:
  void ApplySettings();
  void ShowReadout();
  void ShowTargetView();
  void ToggleStream(bool on);
  void OnTimer();

  vtkRPNavigationLogic* Logic;
  std::unique_ptr<rp::TargetViewPicture> Picture;
  std::vector<double> PictureShown;  // what the picture shows (pose, plan, volume time): redraw when it changes
  bool StructureWarningShown = false;
  qRPScorePanel* Score;  // in ScoreLayout: made here, it takes the logic at construction
  QTimer* Timer;
  bool WarningShown = false;
  bool Refreshing = false;
  std::unique_ptr<rp::SceneNodesWatch> SceneWatch;  // nodes added/removed: refresh the lists on the next tick
};

#endif
