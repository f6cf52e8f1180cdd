#ifndef qRPTrackingPanel_h
#define qRPTrackingPanel_h
// The Tracking module's Qt panel (the layout is qRPTrackingPanel.ui): connect any registered pose source (an NDI tracker on a
// serial port, an OpenIGTLink server, a recording, the simulated Polaris) through
// vtkRPTrackingLogic; a table of tools with status, rate and frame counts; pivot calibration
// of the stylus. Nodes follow the source as soon as it publishes (its ReadyFd wakes the main
// thread; at most every MinUpdateMs) and a 30 Hz timer refreshes staleness and the table.
#include <QWidget>

#include <string>
#include <vector>

#include "ui_qRPTrackingPanel.h"

class QSocketNotifier;
class QTimer;
class vtkRPTrackingLogic;

namespace rp {
class PoseSource;
struct ToolPose;
}  // namespace rp

/// The widgets (Ui::qRPTrackingPanel) are private: tests and scripts reach them through the
/// accessors below.
class qRPTrackingPanel : public QWidget, private Ui::qRPTrackingPanel {
  Q_OBJECT
 public:
  static constexpr int MinUpdateMs = 8;  // nodes are not updated faster than this (~120 Hz)
  qRPTrackingPanel(vtkRPTrackingLogic* logic, QWidget* parent = nullptr);
  ~qRPTrackingPanel() override;

  /// Connects a source of a registered kind ("serial", "igtl", "replay", "simulator", ...);
  /// false with the reason in StatusText().
  bool ConnectSource(const QString& kind, const QString& address, const QStringList& toolFiles);
  void Disconnect();
  bool IsConnected() const;
  /// The connected source (nullptr when none), e.g. for its statistics.
  rp::PoseSource* Source() const;
  /// Collects the stylus poses for `seconds`, then calibrates and adds StylusTipToStylus.
  /// An empty node name means the stylus, StylusToTracker.
  void StartPivotCalibration(double seconds, const QString& toolNodeName = QString());
  QString StatusText() const;
  QString PivotText() const;
  QTableWidget* ToolTable() const { return this->Table; }
  /// One refresh (public for tests): update nodes, table, pivot collection.
  void Update();

 private:
  void OnConnectClicked();
  void OnSourceReady();
  void ShowAddressHint();

  vtkRPTrackingLogic* Logic;
  QTimer* Timer;
  QTimer* Coalesce;  // a wake-up that came too soon after an update
  std::vector<QSocketNotifier*> Notifiers;
  int SourceId = -1;
  double LastUpdate = 0;
  double PivotEnd = 0;
  std::string PivotTool;
  std::vector<rp::ToolPose> PivotPoses;
  uint64_t PivotLastCount = 0;
};

#endif
