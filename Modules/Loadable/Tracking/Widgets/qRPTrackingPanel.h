#ifndef qRPTrackingPanel_h
#define qRPTrackingPanel_h
// The Tracking module's Qt panel: connect to an NDI tracker (serial), an OpenIGTLink server or
// the built-in Polaris simulator; a table of tools with status, rate and dropped count; pivot
// calibration of the stylus. A 30 Hz timer drives vtkRPTrackingLogic::UpdateNodes (main thread).
#include <QWidget>

#include <memory>
#include <string>
#include <vector>

class QComboBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QTableWidget;
class QTimer;
class vtkRPTrackingLogic;

namespace rp {
class IgtlClient;
class NdiTracker;
class PolarisSimulator;
class ToolPoseTable;
struct ToolPose;
}  // namespace rp

class qRPTrackingPanel : public QWidget {
  Q_OBJECT
 public:
  enum SourceKind { Serial = 0, OpenIGTLink = 1, Simulator = 2 };
  qRPTrackingPanel(vtkRPTrackingLogic* logic, QWidget* parent = nullptr);
  ~qRPTrackingPanel() override;

  /// Connects; false with the reason in StatusText().
  bool ConnectSource(SourceKind kind, const QString& address, const QStringList& toolFiles);
  void Disconnect();
  bool IsConnected() const;
  /// Collects the stylus poses for `seconds`, then calibrates and adds StylusTipToStylus.
  void StartPivotCalibration(double seconds, const QString& toolNodeName = "StylusToTracker");
  QString StatusText() const;
  QString PivotText() const;
  QTableWidget* ToolTable() const { return this->Table; }
  /// One timer tick (public for tests): update nodes, table, pivot collection.
  void Update();

 private:
  void OnConnectClicked();
  const rp::ToolPoseTable* Poses() const;

  vtkRPTrackingLogic* Logic;
  QComboBox* Source;
  QLineEdit* Address;
  QLineEdit* Tools;
  QPushButton* ConnectButton;
  QPushButton* PivotButton;
  QLabel* State;
  QLabel* Pivot;
  QTableWidget* Table;
  QTimer* Timer;
  std::unique_ptr<rp::PolarisSimulator> Sim;
  std::unique_ptr<rp::NdiTracker> Tracker;
  std::unique_ptr<rp::IgtlClient> Client;
  int SourceId = -1;
  double PivotEnd = 0;
  std::string PivotTool;
  std::vector<rp::ToolPose> PivotPoses;
  uint64_t PivotLastCount = 0;
};

#endif
