#ifndef qRPDrillingPanel_h
#define qRPDrillingPanel_h
// The Drilling module's Qt panel (the layout is qRPDrillingPanel.ui): choose the bone and protected segments (and a CT for cortical /
// trabecular), build the voxel bone, then drill with the simulated device (burr moved with the
// R/A/S spin boxes) or following a tracked tool: burr on/off, radius, speed, undo the last
// stroke, reset; read-outs of the removed volume per tissue, the distance to the protected
// structure (red when it warns or stopped the burr), force and timings; the drill path
// recording and a picture of the tunnel. The Guidance group (qRPFixtureChoiceWidget) switches the
// plan's virtual fixtures on and off, before drilling or while the servo runs
// (vtkRPDrillingLogic::SetPlanFixtures); "Execute plan with simulated hand" drills the chosen
// trajectory with a trembling, drifting hand and those fixtures (rp::DrillPlannedTrajectory, the
// run `roboplan drill --plan` and the demo make) and shows its score against the plan, the window
// kept painted with a progress bar. A 30 Hz timer drives vtkRPDrillingLogic::Update.
#include <QWidget>

#include "rpGuidedDrill.h"
#include "ui_qRPDrillingPanel.h"

class QTimer;
class vtkRPDrillingLogic;

/// The widgets (Ui::qRPDrillingPanel) are private: tests and scripts reach them through the
/// accessors below.
class qRPDrillingPanel : public QWidget, private Ui::qRPDrillingPanel {
  Q_OBJECT
 public:
  explicit qRPDrillingPanel(vtkRPDrillingLogic* logic, QWidget* parent = nullptr);
  ~qRPDrillingPanel() override;

  /// Refills the segmentation, segment and volume choices from the scene.
  void RefreshChoices();
  bool BuildBone();
  bool Start();
  void Stop();
  bool IsRunning() const;
  /// One timer tick (public for tests).
  void Update();
  bool SavePicture(const QString& path);
  /// Drills the Guidance group's trajectory with the simulated hand (tremor, drift, speed, seed
  /// of the spin boxes) and its fixtures, on a freshly built bone when the box says so, and shows
  /// the score. False with the reason in ExecutionText().
  bool ExecutePlan();

  QComboBox* SegmentationComboBox() const { return this->Segmentation; }
  QListWidget* BoneList() const { return this->BoneSegments; }
  QListWidget* ProtectedList() const { return this->ProtectedSegments; }
  QComboBox* CTComboBox() const { return this->CT; }
  QComboBox* DriveComboBox() const { return this->Drive; }
  QDoubleSpinBox* VoxelSpinBox() const { return this->Voxel; }
  QDoubleSpinBox* RadiusSpinBox() const { return this->Radius; }
  QDoubleSpinBox* RpmSpinBox() const { return this->Rpm; }
  QDoubleSpinBox* BurrSpinBox(int axis) const { return this->Burr[axis]; }
  QPushButton* BuildButton() const { return this->Build; }
  QPushButton* StartStopButton() const { return this->StartStop; }
  QPushButton* BurrButton() const { return this->BurrOn; }
  QPushButton* UndoButton() const { return this->UndoStroke; }
  QPushButton* ResetButton() const { return this->ResetBone; }
  QLineEdit* RecordPathEdit() const { return this->RecordPath; }
  /// The Guidance group: the plan's virtual fixtures.
  qRPFixtureChoiceWidget* GuidanceWidget() const { return this->Guidance; }
  QDoubleSpinBox* TremorSpinBox() const { return this->Tremor; }
  QDoubleSpinBox* DriftSpinBox() const { return this->Drift; }
  QDoubleSpinBox* HandSpeedSpinBox() const { return this->HandSpeed; }
  QSpinBox* SeedSpinBox() const { return this->Seed; }
  QCheckBox* FreshBoneCheckBox() const { return this->FreshBone; }
  QPushButton* ExecuteButton() const { return this->Execute; }
  QProgressBar* ExecuteProgressBar() const { return this->Progress; }
  /// The last execution's score (or why it did not run), and the run itself.
  QString ExecutionText() const;
  const rp::GuidedDrillResult& LastExecution() const { return this->Last; }
  QString StatusText() const;
  QString BoneText() const;
  QString RemovedText() const;
  QString ProtectedText() const;
  /// True when the distance read-out shows its warning colour.
  bool ProtectedWarning() const { return this->Warning; }
  double RemovedTotal() const { return this->Removed; }

 private:
  void SendBurrPosition();
  void FitBurrRange();

  vtkRPDrillingLogic* Logic;
  QDoubleSpinBox* Burr[3];  // BurrR, BurrA, BurrS
  QTimer* Timer;
  rp::GuidedDrillResult Last;
  bool Warning = false;
  double Removed = 0;
};

#endif
