#ifndef vtkRPVolumeSliceDisplayableManager_h
#define vtkRPVolumeSliceDisplayableManager_h
// Scalar volumes as their slice nodes show them (the pictures come from vtkRPSliceLogic, one per
// slice node, shared by every view), each as a textured quad: in a slice view, the node's
// picture on its plane (colours on black); in the 3D view, every slice node's picture placed in RAS where the node's
// SliceVisible is on, drawn only where there is patient (air is cut away, so the models behind
// show through) and depth-tested as opaque geometry, so the three planes cross correctly; in 3D
// they are drawn with what moves (layer 1), so the models' picture is kept while they move.
#include <vector>

#include <vtkSmartPointer.h>

#include "vtkRPDisplayableManager.h"

class vtkActor;
class vtkCallbackCommand;
class vtkRenderer;
class vtkRPSliceLogic;
namespace rp {
class View;
}

class vtkRPVolumeSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPVolumeSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPVolumeSliceDisplayableManager, vtkRPDisplayableManager);

  /// The textured quad of picture i: in a slice view its one picture (i = 0); in 3D slice
  /// node i's (0 axial/Red, 1 sagittal/Yellow, 2 coronal/Green).
  vtkActor* GetSliceActor(int i) const;
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
  /// The renderer the pictures go to: a slice view's layer 0, the 3D view's layer 1.
  static vtkRenderer* LayerOf(rp::View* view);

  std::vector<Picture*> Pictures;
  vtkSmartPointer<vtkCallbackCommand> LogicCallback;
};

#endif
