#ifndef qRPSegmentationToMeshPanel_h
#define qRPSegmentationToMeshPanel_h
// The SegmentationToMesh module's Qt panel, a view of vtkRPSegmentationToMeshLogic (the layout is
// qRPSegmentationToMeshPanel.ui): pick a volume and a target segmentation, segment one tissue
// (threshold preset, manual thresholds, region growing or confidence connected from the seeds of
// a fiducial list), split a CT's bones one by one (the seed list's labels name them), or take the
// volume as a labelmap (one segment per label value, names and colours from a label table), edit
// it (morphology, keep largest), then preview its surface (a temporary "<segment> (preview)"
// model, replaced on each preview) or build the display + haptic models into the scene. Every
// action is one logic call; the panel only reads its widgets and shows the outcome.
#include <QWidget>

#include <string>

#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include "rpSegmentationEditor.h"
#include "ui_qRPSegmentationToMeshPanel.h"

class vtkObject;
class vtkRPScalarVolumeNode;
class vtkRPSegmentationNode;
class vtkRPSegmentationToMeshLogic;

namespace rp {
struct ModelBuildOptions;
struct TissueRecipe;
}

/// The widgets (Ui::qRPSegmentationToMeshPanel: VolumeCombo, ApplyButton, StatusLabel, ...) are
/// public members, for tests and scripting.
class qRPSegmentationToMeshPanel : public QWidget, public Ui::qRPSegmentationToMeshPanel {
  Q_OBJECT
 public:
  /// MethodCombo's entries.
  enum Method { PresetThreshold = 0, ManualThreshold = 1, RegionGrowing = 2, ConfidenceConnected = 3 };

  explicit qRPSegmentationToMeshPanel(vtkRPSegmentationToMeshLogic* logic, QWidget* parent = nullptr);
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
  std::string PreviewNodeID() const;
  QString StatusText() const;
  bool HasError() const { return this->Error; }

 private:
  void ConnectWidgets();
  void FillChoices();
  void OnSceneEvent(vtkObject* caller, unsigned long event, void* callData);
  void OnSegmentationModified(vtkObject* caller, unsigned long event, void* callData);
  void ObserveSegmentation(vtkRPSegmentationNode* segmentation);
  void RefreshNodeCombos();
  void RefreshSegments(const std::string& select = "");
  void SelectSegmentation(vtkRPSegmentationNode* segmentation);
  void OnPresetChanged();
  void OnMethodChanged();
  /// What Apply runs: the target segment and the method, from the widgets. False with `error`.
  bool Recipe(rp::TissueRecipe& recipe, QString& error) const;
  rp::ModelBuildOptions BuildOptions() const;
  /// One edit of the current segment, `what` naming it in messages.
  bool Edit(int edit, const QString& what);
  void ShowError(const QString& text);
  void ShowStatus(const QString& text);

  vtkSmartPointer<vtkRPSegmentationToMeshLogic> Logic;
  unsigned long SceneObservers[4] = {0, 0, 0, 0};
  /// The current segmentation, observed so its segment list follows edits made elsewhere.
  vtkWeakPointer<vtkRPSegmentationNode> ObservedSegmentation;
  unsigned long SegmentationObserver = 0;
  bool Error = false;
};

#endif
