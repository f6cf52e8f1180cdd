#pragma once
// The views of one scene and what the user does with them, without Qt: the view state (slice
// point, layers, layout), the four views, slice navigation, window/level, fiducial placement and
// following a transform node's tip (navigation drives the slices from a tracked tool). Qt hosts
// and the headless screenshot use it alike.
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
class vtkRPScalarVolumeNode;
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
  vtkRPViewState* GetViewState() const { return this->State; }
  View* GetView(ViewKind kind) const { return this->Views[static_cast<size_t>(kind)].get(); }

  /// Moves the point where the three slice views cut; every view follows.
  void SetSlicePointRAS(const double ras[3]);
  void GetSlicePointRAS(double ras[3]) const;
  /// Slices follow the origin (the tip) of a transform node's frame, in world RAS, whenever it
  /// or a parent moves. "" stops following.
  void SetFollowTransformNodeID(const std::string& id);
  const std::string& GetFollowTransformNodeID() const { return this->FollowID; }

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

  vtkRPScalarVolumeNode* GetBackgroundVolume() const;
  vtkRPScalarVolumeNode* GetForegroundVolume() const;
  /// Mouse drag on a slice: dx widens the window, dy raises the level, scaled to the volume's range.
  void AdjustWindowLevel(double dx, double dy);
  bool ApplyWindowLevelPreset(WindowLevelPreset preset);

  /// Slice point to the centre of the background volume and every camera reset.
  void ResetViews();
  void ResetCameras();

 private:
  static void OnSceneEvent(vtkObject*, unsigned long event, void* clientData, void* callData);
  static void OnFollowedModified(vtkObject*, unsigned long, void* clientData, void*);
  void OnNodeAdded(vtkObject* node);
  void OnNodeAboutToBeRemoved(vtkObject* node);
  void UpdateFromFollowed();

  vtkWeakPointer<vtkRPScene> Scene;  // weak: a scene deleted first must not crash the views
  vtkNew<vtkRPViewState> State;
  std::array<std::unique_ptr<View>, 4> Views;
  vtkNew<vtkCallbackCommand> SceneCallback;
  vtkNew<vtkCallbackCommand> FollowCallback;
  unsigned long SceneTags[2] = {0, 0};
  std::string FollowID;
  vtkWeakPointer<vtkObject> Followed;
  unsigned long FollowTags[2] = {0, 0};
};

}  // namespace rp
