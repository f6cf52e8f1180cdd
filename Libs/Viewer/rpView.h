#pragma once
// One view (axial, sagittal, coronal or 3D): its renderers, its displayable managers and its
// camera. A slice view shows one slice node of the scene (Red, Yellow or Green): its camera
// follows the node's plane, field of view and pan; zooming and panning change the node. The 3D
// view shows every slice node's picture in RAS. A view renders into any render window at a
// viewport, so the same code draws in a Qt widget and in an offscreen window for screenshots.
// Every view has two layers: slice views the image (layer 0) and overlays (layer 1: outlines,
// fiducials, tools, crosshair) drawn on top; the 3D view the models (layer 0, kept between
// frames while they stand still) and what moves (layer 1: tools, slices, fiducials). Displayable managers ask for a render; the host renders views
// whose NeedsRender() is true.
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkWeakPointer.h>

#include "rpGlyphText.h"
#include "rpSliceGeometry.h"

class vtkActor;
class vtkObject;
class vtkCallbackCommand;
class vtkLineSource;
class vtkRenderWindow;
class vtkRenderer;
class vtkRPCachedRenderPass;
class vtkRPDisplayableManager;
class vtkRPScene;
class vtkRPSliceLogic;
class vtkRPSliceNode;
class vtkRPViewState;
class vtkTextActor;

namespace rp {

class OrientationMarker;

/// The slice nodes of the three slice views and their pictures, indexed by ViewKind.
struct SliceViewNodes {
  std::array<vtkRPSliceNode*, 3> Nodes{};
  std::array<vtkRPSliceLogic*, 3> Logics{};
};

class View {
 public:
  View(ViewKind kind, vtkRPScene* scene, vtkRPViewState* state, const SliceViewNodes& slices);
  ~View();
  View(const View&) = delete;
  View& operator=(const View&) = delete;

  ViewKind GetKind() const { return this->Kind; }
  bool IsSlice() const { return IsSliceView(this->Kind); }
  vtkRPScene* GetScene() const { return this->Scene; }
  vtkRPViewState* GetViewState() const { return this->State; }
  /// The slice node this view shows (slice views), or nullptr (3D).
  vtkRPSliceNode* GetSliceNode() const;
  /// The picture of this view's slice node (slice views), or nullptr (3D).
  vtkRPSliceLogic* GetSliceLogic() const;
  /// Every slice node and picture (the 3D view draws them all).
  const SliceViewNodes& GetSliceViewNodes() const { return this->Slices; }

  /// Layer 0: the image in slice views; in 3D the models (their picture kept between frames).
  vtkRenderer* GetRenderer() const { return this->Renderer; }
  /// Layer 1, drawn every frame on top: outlines, fiducials, tools, crosshair in slice views;
  /// tools, fiducials and the slices in 3D (depth-tested against the models there).
  vtkRenderer* GetOverlayRenderer() const;
  /// 3D: keep the models' picture between frames while they stand still (on by default); off
  /// renders every model every frame.
  void SetModelLayerCaching(bool caching);
  bool GetModelLayerCaching() const;
  /// 3D: the pass that keeps the models' picture (frames rendered and copied).
  vtkRPCachedRenderPass* GetModelLayerPass() const { return this->ModelLayer; }

  /// Adds the view's renderers to a window at a viewport (xmin, ymin, xmax, ymax in 0..1).
  void AttachToRenderWindow(vtkRenderWindow* window, const double viewport[4]);
  void DetachFromRenderWindow();
  vtkRenderWindow* GetRenderWindow() const { return this->Window; }

  void RequestRender();
  bool NeedsRender() const { return this->RenderRequested; }
  /// Slice views: starts making the slice picture on a worker thread (vtkRPSliceLogic::
  /// StartPicture), for a render that comes after another view's; WaitForPicture() waits for it.
  void StartPicture();
  void WaitForPicture();
  /// Clears the flag (the host calls this when it renders the window).
  void MarkRendered() { this->RenderRequested = false; }
  /// Interactive level of detail (a tool moving): managers may draw lighter (decimated display
  /// meshes). Set by rp::RenderScheduler before each render.
  void SetInteractive(bool interactive);
  bool GetInteractive() const { return this->Interactive; }
  /// Called on every RequestRender (e.g. to wake a host); optional.
  void SetRenderRequestCallback(std::function<void()> callback) { this->OnRenderRequest = std::move(callback); }

  /// Slice views: the node's field of view fits the background volume (or 250 mm), centred on
  /// it. 3D: the visible models (else the volumes, else 250 mm) fill the view, seen from the
  /// front (the patient's anterior), head up.
  void ResetCamera();
  /// Slice views: the RAS point on the slice plane under a display pixel (VTK display
  /// coordinates: origin bottom-left of the window). False for 3D or when outside the viewport.
  bool DisplayToRAS(double x, double y, double ras[3]) const;
  /// Inverse: display pixel of a RAS point.
  void RASToDisplay(const double ras[3], double display[2]) const;
  /// Slice views: distance along the normal of one scroll step (the background's spacing or 1 mm).
  double GetSliceStep() const;
  /// Slice views: the slice offset along the normal (mm).
  double GetSliceOffset() const;
  /// Zoom by a factor (> 1 magnifies) and pan by a RAS offset in the plane; in slice views both
  /// change the slice node (field of view, pan), so they are saved with the scene.
  void Zoom(double factor);
  void Pan(const double deltaRAS[3]);

  /// Displayable managers created for this view kind (volume slices, models, outlines, fiducials, tools).
  const std::vector<vtkSmartPointer<vtkRPDisplayableManager>>& GetDisplayableManagers() const {
    return this->Managers;
  }
  template <class T>
  T* GetDisplayableManager() const {
    for (const auto& manager : this->Managers) {
      if (T* typed = T::SafeDownCast(manager)) return typed;
    }
    return nullptr;
  }

  /// Slice views: the corner text (orientation and offset). The volume slice manager draws it
  /// into the slice picture (DrawCornerText) when it draws one; otherwise a text actor shows it.
  const std::string& GetCornerString() const { return this->CornerString; }
  /// Draws the corner text over an RGBA picture of the view's size (rows from the bottom).
  void DrawCornerText(unsigned char* picture, int width, int height);

 private:
  static void OnSliceNodeModified(vtkObject* caller, unsigned long, void* clientData, void*);
  static void OnRenderStart(vtkObject*, unsigned long, void* clientData, void*);
  void UpdateSliceCamera();
  void UpdateCrosshair();
  void UpdateCornerText();
  double GetViewportAspect() const;
  /// Bounds (RAS) of what the 3D camera should frame: visible models, else volumes.
  bool ComputeFramingBounds(double bounds[6]) const;

  ViewKind Kind;
  vtkRPScene* Scene;
  vtkRPViewState* State;
  SliceViewNodes Slices;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderer> Overlay;
  vtkNew<vtkRPCachedRenderPass> ModelLayer;  // 3D: layer 0's pass
  vtkRenderWindow* Window = nullptr;
  std::vector<vtkSmartPointer<vtkRPDisplayableManager>> Managers;
  vtkNew<vtkCallbackCommand> SliceCallback;
  vtkNew<vtkCallbackCommand> RenderCallback;
  std::vector<std::pair<vtkWeakPointer<vtkRPSliceNode>, unsigned long>> SliceTags;
  unsigned long RenderTag = 0;
  vtkNew<vtkLineSource> CrossLines[2];
  vtkNew<vtkActor> CrossActors[2];
  vtkNew<vtkTextActor> CornerText;  // 3D; slice views while no picture carries the text
  std::string CornerString;
  GlyphText CornerGlyphs;  // slice views: the text drawn into the picture
  std::unique_ptr<OrientationMarker> Marker;  // 3D: patient axes in a corner
  double LastAspect = 0;
  vtkMTimeType CameraTimeAtLastFrame = 0;  // 3D: the camera's modification time at the last SetInteractive
  bool RenderRequested = true;
  bool Interactive = false;
  std::function<void()> OnRenderRequest;
};

}  // namespace rp
