#ifndef qRPDrillingPanel_h
#define qRPDrillingPanel_h
// The Drilling module's Qt panel: choose the bone and protected segments (and a CT for cortical /
// trabecular), build the voxel bone, then drill with the simulated device (burr moved with the
// R/A/S spin boxes) or following a tracked tool: burr on/off, radius, speed, undo the last
// stroke, reset; read-outs of the removed volume per tissue, the distance to the protected
// structure (red when it warns or stopped the burr), force and timings; the drill path
// recording and a picture of the tunnel. A 30 Hz timer drives vtkRPDrillingLogic::Update.
#include <QWidget>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QPushButton;
class QTimer;
class vtkRPDrillingLogic;

class qRPDrillingPanel : public QWidget {
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
  QComboBox* Segmentation;
  QListWidget* BoneSegments;
  QListWidget* ProtectedSegments;
  QComboBox* CT;
  QComboBox* Drive;
  QDoubleSpinBox* Voxel;
  QDoubleSpinBox* Radius;
  QDoubleSpinBox* Rpm;
  QDoubleSpinBox* Burr[3];
  QPushButton* Build;
  QPushButton* StartStop;
  QPushButton* BurrOn;
  QPushButton* UndoStroke;
  QPushButton* ResetBone;
  QPushButton* Picture;
  QLineEdit* RecordPath;
  QLabel* State;
  QLabel* BoneInfo;
  QLabel* RemovedInfo;
  QLabel* ProtectedInfo;
  QLabel* ForceInfo;
  QLabel* Timing;
  QTimer* Timer;
  bool Warning = false;
  double Removed = 0;
};

#endif
