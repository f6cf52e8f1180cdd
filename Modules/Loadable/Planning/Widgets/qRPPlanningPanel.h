#ifndef qRPPlanningPanel_h
#define qRPPlanningPanel_h
// The Planning module's Qt panel. Pick the CT and segmentation; make a trajectory, screw or cut
// plane ("New ...": the next clicks in the views place its entry and target, or origin; drag the
// points in the slice and 3D views); set its tool, screw and tissue; flag models and segments as
// structures at risk with a margin (stored on them: the one notion drilling and guidance read);
// read the figures, which follow the plan at display rate (a 30 Hz timer recomputes when the plan
// or a structure changed): length, length in bone, breach and its grade, cortical share,
// clearance per structure (red under the margin) and the HU profile; propose an entry from a
// region (the risk map follows a dragged target with "Follow the target"). vtkRPPlanningLogic
// does the work; the panel never draws in a view. The layout is qRPPlanningPanel.ui.
#include <QWidget>

#include <memory>
#include <string>
#include <vector>

#include "rpSceneNodesWatch.h"
#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"
#include "ui_qRPPlanningPanel.h"

class QTimer;
class vtkRPPlanningLogic;
class vtkRPNode;

/// The widgets (Ui::qRPPlanningPanel) are private: the accessors below are the panel's interface.
class qRPPlanningPanel : public QWidget, private Ui::qRPPlanningPanel {
  Q_OBJECT
 public:
  explicit qRPPlanningPanel(vtkRPPlanningLogic* logic, QWidget* parent = nullptr);
  ~qRPPlanningPanel() override;

  /// Re-reads the scene's volumes, segmentations, plans and structures (keeps the choices).
  void RefreshNodeLists();
  /// Recomputes the current plan's figures now.
  void UpdateFigures();
  /// Creates a plan of this class ("vtkRPTrajectoryNode", "vtkRPScrewNode", "vtkRPCutPlaneNode")
  /// and makes it current; the views place its points next.
  vtkRPNode* NewPlan(const char* className);
  /// Scores the entry region's candidates for the current trajectory's target (risk map updated).
  bool Propose();

  QComboBox* VolumeComboBox() const { return this->Volume; }
  QComboBox* SegmentationComboBox() const { return this->Segmentation; }
  QComboBox* PlanComboBox() const { return this->Plan; }
  QComboBox* RegionComboBox() const { return this->Region; }
  QDoubleSpinBox* DiameterSpinBox() const { return this->Diameter; }
  QTableWidget* StructureTable() const { return this->Structures; }
  QTableWidget* ClearanceTable() const { return this->Clearances; }
  QCheckBox* FollowTargetCheckBox() const { return this->FollowTarget; }
  QString FiguresText() const;
  QString ProblemText() const;
  QString ProposalText() const;
  const rp::TrajectoryFigures& Figures() const { return this->LastFigures; }
  const rp::ProposalResult& LastProposal() const { return this->LastProposalResult; }
  /// How many times the figures were recomputed (tests check they follow a drag).
  int NumberOfFigureUpdates() const { return this->FigureUpdates; }

 protected:
  void showEvent(QShowEvent* event) override;

 private:
  void ConnectWidgets();
  void ApplyPatient();
  void ApplyPlanSettings();
  void ShowPlanSettings();
  void ApplyStructureRow(int row);
  void RefreshStructures();
  void ShowFigures(const rp::TrajectoryFigures& figures);
  void ShowCut();
  void OnTimer();
  unsigned long WatchedTime() const;
  vtkRPNode* CurrentPlan() const;

  vtkRPPlanningLogic* Logic;
  QTimer* Timer;
  rp::TrajectoryFigures LastFigures;
  rp::ProposalResult LastProposalResult;
  std::string RegionShown;  // the entry region the logic holds candidates of
  unsigned long ShownTime = 0;
  int FigureUpdates = 0;
  bool Refreshing = false;
  std::unique_ptr<rp::SceneNodesWatch> SceneWatch;  // nodes added/removed: refresh the lists on the next tick
};

#endif
