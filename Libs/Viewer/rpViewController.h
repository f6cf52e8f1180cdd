#pragma once
// The views of one scene and what the user does with them, without Qt. The view state is the
// scene's: each slice view shows a slice node (Red axial, Yellow sagittal, Green coronal, added
// to the scene when missing) and the layout is the scene's layout node, so modules drive the
// views by changing nodes, and a saved scene reopens as it was. The controller is the observer
// that keeps the views in step (Slicer's displayable-manager pattern): it gives new volumes and
// segmentations a layer when the slice nodes have none, frames the views on load, and owns one
// slice picture (vtkRPSliceLogic) per slice node that every view shares. Qt hosts and the
// headless screenshot use it alike.
#include <array>
#include <memory>
#include <string>

#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include "rpSliceGeometry.h"
#include "vtkRPScene.h"

class vtkCallbackCommand;
class vtkRPFiducialListNode;
class vtkRPLayoutNode;
class vtkRPScalarVolumeNode;
class vtkRPSliceLogic;
class vtkRPSliceNode;
class vtkRPViewState;

namespace rp {

class View;

enum class WindowLevelPreset { CTBone, CTSoftTissue, MR };
/// Window and level of a preset (MR uses the volume's intensities: 1st to 99th percentile).
bool GetWindowLevelPreset(WindowLevelPreset preset, vtkRPScalarVolumeNode* volume, double& window, double& level);

class ViewController {
 public:
  explicit ViewController(vtkRPScene* scene);
  ~ViewController();
  ViewController(const ViewController&) = delete;
  ViewController& operator=(const ViewController&) = delete;

  vtkRPScene* GetScene() const { return this->Scene; }
  /// The viewer's own interaction state (mode, active fiducial list); not saved with the scene.
  vtkRPViewState* GetViewState() const { return this->State; }
  View* GetView(ViewKind kind) const { return this->Views[static_cast<size_t>(kind)].get(); }
  /// The slice node a slice view shows (nullptr for ThreeD).
  vtkRPSliceNode* GetSliceNode(ViewKind kind) const;
  /// The picture of a slice view's node, shared with the 3D view (nullptr for ThreeD).
  vtkRPSliceLogic* GetSliceLogic(ViewKind kind) const;
  /// The scene's layout node (which views the host shows).
  vtkRPLayoutNode* GetLayoutNode() const;

  // ---- conveniences that change all three slice nodes
  /// Every slice plane passes through `ras` (the crosshair's point).
  void SetSlicePointRAS(const double ras[3]);
  /// Where the three slice planes meet (the Red plane's origin if two are parallel).
  void GetSlicePointRAS(double ras[3]) const;
  /// The slices follow the origin (the tip) of a transformable node, in world RAS, whenever it
  /// or a parent moves. "" stops following.
  void SetFollowTransformNodeID(const std::string& id);
  std::string GetFollowTransformNodeID() const;
  void SetBackgroundVolumeID(const std::string& id);
  void SetForegroundVolumeID(const std::string& id);
  void SetForegroundOpacity(double opacity);
  /// Whether the three slices are drawn in the 3D view.
  void SetSlicesVisibleIn3D(bool visible);
  bool GetSlicesVisibleIn3D() const;
  /// The layers the Red (axial) slice shows.
  vtkRPScalarVolumeNode* GetBackgroundVolume() const;
  vtkRPScalarVolumeNode* GetForegroundVolume() const;

  /// Scroll: moves the slice of one view by whole steps along its normal.
  void MoveSlice(ViewKind kind, int steps);
  /// A click at a display pixel of a slice view: sets the slice point there, or adds a fiducial
  /// in ModePlaceFiducial. Returns false if the view is not a slice view.
  bool ClickInSliceView(ViewKind kind, double x, double y);
  /// A click at a display pixel of the 3D view in ModePlaceFiducial: adds a fiducial where the
  /// pixel's ray first hits a model or a slice. Returns false when nothing was hit (or not placing).
  bool ClickIn3DView(double x, double y);
  /// Adds a point to the active fiducial list (created, and made active, when missing).
  vtkRPFiducialListNode* PlaceFiducial(const double ras[3]);

  /// The fiducial drawn nearest a display pixel of a slice view, within `pixels`; false if none.
  bool FindFiducialAt(ViewKind kind, double x, double y, double pixels, std::string& listID, int& index) const;
  /// Moves a control point to a world RAS position (refused for locked points).
  bool MoveFiducial(const std::string& listID, int index, const double ras[3]);

  /// Mouse drag on a slice: dx widens the window, dy raises the level, scaled to the volume's range.
  void AdjustWindowLevel(double dx, double dy);
  bool ApplyWindowLevelPreset(WindowLevelPreset preset);

  /// Slice point to the centre of the background volume, every slice view fitted to it and the
  /// 3D camera framing the visible models from the front.
  void ResetViews();
  void ResetCameras();
  /// The 3D camera only (framing the visible models from the front).
  void ResetCameras3D();

 private:
  static void OnSceneEvent(vtkObject*, unsigned long event, void* clientData, void* callData);
  void OnNodeAdded(vtkObject* node);
  void OnNodeAboutToBeRemoved(vtkObject* node);
  void OnNodeRemoved(vtkObject* node);
  void OnEndImport();
  /// Gives slice nodes without a label layer the first segmentation, without a (valid)
  /// background the volume that segmentation was drawn on (else the first volume), and a
  /// foreground the next volume. True when a background was given, or a segmentation to show
  /// alone (the views are to be fitted to it).
  bool AssignDefaultLayers();
  bool HasFramingContent() const;

  vtkWeakPointer<vtkRPScene> Scene;  // weak: a scene deleted first must not crash the views
  vtkNew<vtkRPViewState> State;
  std::array<vtkSmartPointer<vtkRPSliceNode>, 3> SliceNodes;  // kept alive: re-added if removed
  std::array<vtkSmartPointer<vtkRPSliceLogic>, 3> SliceLogics;
  vtkSmartPointer<vtkRPLayoutNode> Layout;
  std::array<std::unique_ptr<View>, 4> Views;
  vtkNew<vtkCallbackCommand> SceneCallback;
  std::vector<unsigned long> SceneTags;
  bool Has3DContent = false;  // the 3D camera was framed on something
};

}  // namespace rp
