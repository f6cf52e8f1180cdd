#ifndef vtkRPVolumeSliceDisplayableManager_h
#define vtkRPVolumeSliceDisplayableManager_h
// Scalar volumes as their slice nodes show them (the pictures come from vtkRPSliceLogic, one per
// slice node, shared by every view). In a slice view, the node's picture resampled onto the
// view's pixels when it renders (colours on black) and copied into the framebuffer as it is
// (vtkRPViewportImageActor): a software rasterizer spent more on a textured quad covering the
// view than on the rest of the view. In the 3D view, every slice node's picture as a textured
// quad placed in RAS where the node's SliceVisible is on, drawn only where there is patient (air
// is cut away, so the models behind show through) and depth-tested as opaque geometry, so the
// three planes cross correctly; drawn with what moves (layer 1), so the models' picture is kept
// while they move. The quad spans only the picture's patient pixels (their bounding rectangle),
// not the whole plane: a software rasterizer pays for every fragment it cuts away.
#include <vector>

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "vtkRPDisplayableManager.h"

class vtkActor;
class vtkCallbackCommand;
class vtkRenderer;
class vtkRPSliceLogic;
class vtkRPViewportImageActor;
namespace rp {
class View;
}

class vtkRPVolumeSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPVolumeSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPVolumeSliceDisplayableManager, vtkRPDisplayableManager);

  /// 3D: the textured quad of slice node i's picture (0 axial/Red, 1 sagittal/Yellow, 2
  /// coronal/Green); nullptr in a slice view.
  vtkActor* GetSliceActor(int i) const;
  /// A slice view: its picture at the view's pixels; nullptr in 3D.
  vtkRPViewportImageActor* GetScreenPictureActor() const;
  /// Pictures shown (one in a slice view, three in 3D) that have an image.
  int GetNumberOfVisibleSlices() const;

 protected:
  vtkRPVolumeSliceDisplayableManager();
  ~vtkRPVolumeSliceDisplayableManager() override;
  // The volumes reach the views through the slice logics, not as displayed nodes.
  bool CanDisplay(vtkRPNode*) const override { return false; }
  void AddDisplay(vtkRPNode*) override {}
  void RemoveDisplay(vtkRPNode*) override {}
  void UpdateDisplay(vtkRPNode*) override {}
  void OnViewStateModified() override;
  void OnInitialize() override;
  void OnFinalize() override;

 private:
  vtkRPVolumeSliceDisplayableManager(const vtkRPVolumeSliceDisplayableManager&) = delete;
  void operator=(const vtkRPVolumeSliceDisplayableManager&) = delete;
  struct Picture;
  static void OnLogicModified(vtkObject* caller, unsigned long, void* clientData, void*);
  void UpdatePicture(Picture& picture);
  void UpdateScreenPicture(Picture& picture);
  void UpdateQuad(Picture& picture);
  bool InSliceView() const;  // a slice view (else the 3D view)

  std::vector<Picture*> Pictures;
  vtkSmartPointer<vtkCallbackCommand> LogicCallback;
  // Observed as it starts rendering: a slice view's layer 0, to make the screen picture; the 3D
  // view's layer 1, to fit the quads to their pictures.
  vtkNew<vtkCallbackCommand> RenderCallback;
  vtkRenderer* RenderTarget = nullptr;
  unsigned long RenderTag = 0;
};

#endif
