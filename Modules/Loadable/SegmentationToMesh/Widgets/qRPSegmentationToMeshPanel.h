#ifndef qRPSegmentationToMeshPanel_h
#define qRPSegmentationToMeshPanel_h
// The SegmentationToMesh module's Qt panel: pick a volume and a target segmentation, segment one
// tissue (threshold preset, manual thresholds, region growing or confidence connected from the
// seeds of a fiducial list), split a CT's bones one by one (the seed list's labels name them), or
// take the volume as a labelmap (one segment per label value, names and colours from a label
// table), edit it (morphology, keep largest), then preview its surface (a temporary
// "<segment> (preview)" model, replaced on each preview) or build the display + haptic models into
// the scene. The panel only edits scene nodes; the viewer draws them.
#include <QWidget>

#include <map>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include "rpSegmentationEditor.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLayout;
class QLineEdit;
class QPushButton;
class QSpinBox;
class vtkObject;
class vtkRPNode;
class vtkRPScalarVolumeNode;
class vtkRPScene;
class vtkRPSegmentationNode;

namespace rp {
struct ModelBuildOptions;
}

class qRPSegmentationToMeshPanel : public QWidget {
  Q_OBJECT
 public:
  enum Method { PresetThreshold = 0, ManualThreshold = 1, RegionGrowing = 2, ConfidenceConnected = 3 };

  explicit qRPSegmentationToMeshPanel(vtkRPScene* scene, QWidget* parent = nullptr);
  ~qRPSegmentationToMeshPanel() override;

  /// Each returns false and shows the reason (red) in the status label.
  bool Apply();
  bool ApplyMorphology(rp::Morphology op);
  bool KeepLargest();
  bool Preview();
  bool CreateModels();
  /// A new empty segmentation node, selected as the target.
  vtkRPSegmentationNode* NewSegmentation();
  /// Bones one by one from the input volume (a CT): a new segmentation, one segment per bone;
  /// the points of the seed list (if any) name bones by their labels or force a split.
  bool SplitBones();
  /// The input volume as a labelmap: a new segmentation (a copy of its voxels), one segment per
  /// label value, named from the label table file when one is given.
  bool LabelmapToSegments();

  vtkRPScalarVolumeNode* CurrentVolume() const;
  vtkRPSegmentationNode* CurrentSegmentation() const;
  std::string CurrentSegmentID() const;
  /// The preview model's node ID ("" when none).
  const std::string& PreviewNodeID() const { return this->PreviewID; }
  QString StatusText() const;
  bool HasError() const { return this->Error; }

  // Widgets (public for tests and scripting).
  QComboBox* VolumeCombo;
  QComboBox* SegmentationCombo;
  QPushButton* NewSegmentationButton;
  QLineEdit* LabelTableEdit;
  QPushButton* LabelTableBrowseButton;
  QPushButton* LabelmapButton;
  QComboBox* MethodCombo;
  QComboBox* PresetCombo;
  QDoubleSpinBox* LowerSpin;
  QDoubleSpinBox* UpperSpin;
  QComboBox* SeedsCombo;
  QDoubleSpinBox* MultiplierSpin;
  QSpinBox* IterationsSpin;
  QLineEdit* SegmentNameEdit;
  QComboBox* TissueCombo;
  QPushButton* ApplyButton;
  QPushButton* SplitBonesButton;
  QComboBox* SegmentCombo;
  QDoubleSpinBox* MorphologyRadiusSpin;
  QPushButton* ClosingButton;
  QPushButton* OpeningButton;
  QPushButton* FillHolesButton;
  QPushButton* KeepLargestButton;
  QComboBox* MeshMethodCombo;
  QDoubleSpinBox* SigmaSpin;
  QDoubleSpinBox* GridStepSpin;
  QSpinBox* DisplayTrianglesSpin;
  QSpinBox* HapticTrianglesSpin;
  QCheckBox* AllSegmentsCheck;
  QPushButton* PreviewButton;
  QPushButton* CreateModelsButton;
  QLabel* StatusLabel;

 private:
  // The constructor's parts: each group of widgets, then the signal connections.
  QLayout* BuildInputForm();
  QWidget* BuildMethodBox();
  QWidget* BuildEditBox();
  QWidget* BuildSurfaceBox();
  void ConnectWidgets();
  void OnSceneEvent(vtkObject* caller, unsigned long event, void* callData);
  void OnSegmentationModified(vtkObject* caller, unsigned long event, void* callData);
  void ObserveSegmentation(vtkRPSegmentationNode* segmentation);
  void RefreshNodeCombos();
  void RefreshSegments(const std::string& select = "");
  void OnPresetChanged();
  void OnMethodChanged();
  rp::SegmentTarget Target() const;
  rp::ModelBuildOptions BuildOptions() const;
  void ShowError(const QString& text);
  void ShowStatus(const QString& text);
  void RemovePreview();

  vtkSmartPointer<vtkRPScene> Scene;
  unsigned long SceneObservers[4] = {0, 0, 0, 0};
  std::string PreviewID;
  /// The current segmentation, observed so its segment list follows edits made elsewhere.
  vtkWeakPointer<vtkRPSegmentationNode> ObservedSegmentation;
  unsigned long SegmentationObserver = 0;
  /// Models this panel created per segment ID (replaced by the next "Create models").
  std::map<std::string, std::vector<std::string>> CreatedModelIDs;
  bool Error = false;
};

#endif
