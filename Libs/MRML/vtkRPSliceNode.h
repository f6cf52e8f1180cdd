#ifndef vtkRPSliceNode_h
#define vtkRPSliceNode_h
// What one slice view shows, as scene state (Slicer's vtkMRMLSliceNode, with the layers Slicer
// keeps in vtkMRMLSliceCompositeNode): the plane (orientation preset and SliceToRAS), the field of
// view and pan, the background / foreground / label layers with their opacities, whether the
// slice is drawn in 3D, and the node whose tip the slice follows. Views observe these nodes;
// modules change them, never a view. One singleton per view, tagged by its layout name ("Red"
// axial, "Yellow" sagittal, "Green" coronal, as in Slicer), saved and loaded with the scene.
//
// The standard frames are defined here and only here (GetOrientationMatrix), with Slicer's
// values (vtkMRMLSliceNode::InitializeAxialMatrix etc.): SliceToRAS columns are the screen's
// right, the screen's up and the slice normal.
//   Axial    right = L (−R), up = A, normal = S: seen from the feet, patient's left on screen right
//   Sagittal right = P (−A), up = S, normal = R: seen from the patient's left, anterior on screen left
//   Coronal  right = L (−R), up = S, normal = A: seen from the front, patient's left on screen right
// (Axial and sagittal are left-handed frames, as in Slicer: the normal is the anatomical axis,
// the screen axes are radiological.)
#include <string>
#include <vector>

#include <vtkNew.h>

#include "vtkRPNode.h"

class vtkCallbackCommand;
class vtkMatrix4x4;

class vtkRPSliceNode : public vtkRPNode {
 public:
  static vtkRPSliceNode* New();
  vtkTypeMacro(vtkRPSliceNode, vtkRPNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Slice"; }
  bool GetHideFromEditors() const override { return true; }

  // ---- the standard frames (the one definition)
  /// Rotation part of SliceToRAS for "Axial", "Sagittal" or "Coronal" (columns: right, up,
  /// normal); false for anything else.
  static bool GetOrientationMatrix(const std::string& orientation, double matrix[3][3]);
  /// SliceToRAS of a standard orientation with the plane through `pointRAS` (its translation).
  static bool ComputeSliceToRAS(const std::string& orientation, const double pointRAS[3], vtkMatrix4x4* sliceToRAS);
  /// The plane that contains a tool's shaft (seed section 4): tool x as the slice's right, the
  /// shaft (tool z) as up, normal x × y; through the tip (the tool frame's origin).
  static void ComputeSliceToRASForTool(const vtkMatrix4x4* toolTipToRAS, vtkMatrix4x4* sliceToRAS);
  /// "Red" → "Axial", "Yellow" → "Sagittal", "Green" → "Coronal" (Slicer's defaults); "" otherwise.
  static std::string GetDefaultOrientationForLayoutName(const std::string& layoutName);
  static const char* ReformatOrientationName() { return "Reformat"; }

  // ---- the view this node describes (also its singleton tag)
  const std::string& GetLayoutName() const { return this->GetSingletonTag(); }
  void SetLayoutName(const std::string& name);

  // ---- the plane
  /// "Axial", "Sagittal", "Coronal" or "Reformat" (any other plane, e.g. a tool's).
  const std::string& GetOrientation() const { return this->Orientation; }
  /// Sets a standard orientation, keeping the plane through the current origin. False (and no
  /// change) for an unknown name.
  bool SetOrientation(const std::string& orientation);
  void SetOrientationToAxial() { this->SetOrientation("Axial"); }
  void SetOrientationToSagittal() { this->SetOrientation("Sagittal"); }
  void SetOrientationToCoronal() { this->SetOrientation("Coronal"); }
  /// Slice → RAS: columns right, up, normal (unit); translation a point of the plane. Read-only
  /// (change it with SetSliceToRAS, JumpSlice or SetOrientation so observers hear of it).
  const vtkMatrix4x4* GetSliceToRAS() const { return this->SliceToRAS; }
  void GetSliceToRAS(vtkMatrix4x4* sliceToRAS) const;
  /// Any plane (the orientation becomes the matching preset or "Reformat"). Columns are
  /// re-orthonormalized; a degenerate matrix is refused (false).
  bool SetSliceToRAS(const vtkMatrix4x4* sliceToRAS);
  void GetNormal(double normal[3]) const;
  void GetOrigin(double originRAS[3]) const;
  /// Moves the plane along its normal so it passes through `ras` (Slicer's "offset" jump: the
  /// view does not pan). Non-finite points are ignored.
  void JumpSlice(const double ras[3]);
  /// Signed distance of the plane from RAS 0 along the normal (mm).
  double GetSliceOffset() const;
  void SetSliceOffset(double offset);

  // ---- what the view shows of the plane
  /// Width and height (mm) the view shows at least (zoom).
  vtkGetVector2Macro(FieldOfView, double);
  void SetFieldOfView(double width, double height);
  /// The view's centre in the plane, relative to the plane's origin along right and up (mm; pan).
  vtkGetVector2Macro(XYOrigin, double);
  void SetXYOrigin(double x, double y);
  /// Whether the slice is drawn in 3D views.
  vtkGetMacro(SliceVisible, bool);
  void SetSliceVisible(bool visible);

  // ---- layers (references, so they follow ID remapping on import and removal of the volume)
  static const char* BackgroundVolumeRole() { return "backgroundVolume"; }
  static const char* ForegroundVolumeRole() { return "foregroundVolume"; }
  static const char* LabelRole() { return "label"; }  // a segmentation drawn as label overlay
  static const char* FollowRole() { return "follow"; }
  std::string GetBackgroundVolumeID() const { return this->GetNodeReferenceID(BackgroundVolumeRole()); }
  void SetBackgroundVolumeID(const std::string& id) { this->SetNodeReferenceID(BackgroundVolumeRole(), id); }
  std::string GetForegroundVolumeID() const { return this->GetNodeReferenceID(ForegroundVolumeRole()); }
  void SetForegroundVolumeID(const std::string& id) { this->SetNodeReferenceID(ForegroundVolumeRole(), id); }
  std::string GetLabelNodeID() const { return this->GetNodeReferenceID(LabelRole()); }
  void SetLabelNodeID(const std::string& id) { this->SetNodeReferenceID(LabelRole(), id); }
  vtkGetMacro(ForegroundOpacity, double);
  void SetForegroundOpacity(double opacity);
  vtkGetMacro(LabelOpacity, double);
  void SetLabelOpacity(double opacity);

  // ---- following a tool
  /// The slice follows the origin (the tip) of a transformable node in world RAS whenever it or
  /// a parent moves ("" stops). Refused (false) for a node that is not transformable.
  bool SetAndObserveFollowNodeID(const std::string& id);
  std::string GetFollowNodeID() const { return this->GetNodeReferenceID(FollowRole()); }

  // ---- the scene's slice nodes
  /// The three default views' nodes (Red axial, Yellow sagittal, Green coronal), added to the
  /// scene when missing. Empty for a null scene.
  static std::vector<vtkRPSliceNode*> GetOrAddDefaultSliceNodes(vtkRPScene* scene);
  /// Every slice node in the scene.
  static std::vector<vtkRPSliceNode*> GetSliceNodes(vtkRPScene* scene);
  static vtkRPSliceNode* GetSliceNode(vtkRPScene* scene, const std::string& layoutName);
  /// Every slice plane passes through `ras` (Slicer's JumpAllSlices, offset mode). Adds the
  /// default slice nodes when missing, so the jump is scene state even before a viewer opens.
  static void JumpAllSlices(vtkRPScene* scene, const double ras[3]);
  /// Every slice follows a node's tip ("" stops). Adds the default slice nodes when missing.
  static bool SetAllSlicesFollow(vtkRPScene* scene, const std::string& nodeID);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;
  void UpdateReferences() override;

 protected:
  vtkRPSliceNode();
  ~vtkRPSliceNode() override;
  void OnNodeReferenceChanged(const std::string& role) override;

 private:
  vtkRPSliceNode(const vtkRPSliceNode&) = delete;
  void operator=(const vtkRPSliceNode&) = delete;
  static void OnFollowedEvent(vtkObject* caller, unsigned long event, void* clientData, void*);
  void ObserveFollowedNode();
  void UpdateFromFollowedNode();

  std::string Orientation = "Axial";
  vtkNew<vtkMatrix4x4> SliceToRAS;
  double FieldOfView[2] = {250.0, 250.0};  // Slicer's default
  double XYOrigin[2] = {0.0, 0.0};
  bool SliceVisible = true;
  double ForegroundOpacity = 0.5;
  double LabelOpacity = 0.5;
  vtkObject* Followed = nullptr;  // observed; cleared on its DeleteEvent
  unsigned long FollowTags[3] = {0, 0, 0};
  vtkCallbackCommand* FollowCallback = nullptr;
};

#endif
