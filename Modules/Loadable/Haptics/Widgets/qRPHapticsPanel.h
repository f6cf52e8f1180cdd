#ifndef qRPHapticsPanel_h
#define qRPHapticsPanel_h
// The Haptics module's Qt panel (the layout is qRPHapticsPanel.ui): pick the simulated device (Phantom Omni, Touch), start/stop its
// 1 kHz servo loop on the scene's haptic models, move the simulated stylus tip with R/A/S spin
// boxes (so the module is usable without hardware) or let a tracked tool (a stylus or drill
// under the tracker) drive it, and live read-outs (tissue, force,
// penetration, servo timing) with a warning per tissue the device cannot render stably.
// The Guidance group (qRPFixtureChoiceWidget) switches the plan's virtual fixtures on and off,
// before a session or while the servo runs (vtkRPHapticsLogic::SetPlanFixtures), and says which
// act and, while running, which is engaged. A 30 Hz timer drives vtkRPHapticsLogic::Update (main thread). Destroying the panel stops the
// loop (zero force on the device) and flushes the session log.
#include <QWidget>

#include "ui_qRPHapticsPanel.h"

class QTimer;
class vtkRPHapticsLogic;

/// The widgets (Ui::qRPHapticsPanel) are private: tests and scripts reach them through the
/// accessors below.
class qRPHapticsPanel : public QWidget, private Ui::qRPHapticsPanel {
  Q_OBJECT
 public:
  explicit qRPHapticsPanel(vtkRPHapticsLogic* logic, QWidget* parent = nullptr);
  ~qRPHapticsPanel() override;

  /// Starts the simulated device; false with the reason in StatusText().
  bool Start();
  void Stop();
  bool IsRunning() const;
  /// One timer tick (public for tests): logic update and read-outs.
  void Update();

  QDoubleSpinBox* StylusSpinBox(int axis) const { return this->Stylus[axis]; }
  /// What moves the stylus: the spin boxes (item data "") or a tracked tool node (its ID).
  QComboBox* DriveComboBox() const { return this->Drive; }
  /// Refills the tracked tools that can drive the stylus.
  void RefreshDrives();
  /// The simulated device profile (item data: the profile key, e.g. "omni").
  QComboBox* DeviceComboBox() const { return this->Device; }
  /// "Slices follow the haptic proxy": the scene's slice nodes follow the HapticProxy node (the
  /// views re-slice at the point of contact; the panel never touches a view).
  qRPSliceFollowCheckBox* FollowProxyCheckBox() const { return this->FollowProxy; }
  QPushButton* StartStopButton() const { return this->StartButton; }
  /// The Guidance group: the plan's virtual fixtures.
  qRPFixtureChoiceWidget* GuidanceWidget() const { return this->Guidance; }
  /// Where the session log (CSV, one row per servo tick) goes; empty: no log.
  QLineEdit* LogPathEdit() const { return this->LogPath; }
  QString StatusText() const;
  QString TissueText() const;
  /// The force magnitude shown (N).
  double DisplayedForce() const { return this->ForceN; }
  QString ForceText() const;
  QString PenetrationText() const;
  QString TimingText() const;
  /// One line per tissue the device clamps (requested → rendered stiffness), empty when none.
  QString ClampText() const;

 private:
  void FitRangesToHapticModels();
  void SendStylusPose();

  vtkRPHapticsLogic* Logic;
  QDoubleSpinBox* Stylus[3];  // StylusR, StylusA, StylusS
  QTimer* Timer;
  double ForceN = 0;
};

#endif
