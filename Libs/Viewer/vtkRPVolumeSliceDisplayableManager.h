#ifndef vtkRPVolumeSliceDisplayableManager_h
#define vtkRPVolumeSliceDisplayableManager_h
// Scalar volumes: in a slice view, the background and foreground volumes (chosen in the view
// state) re-sliced on the view's plane through the slice point and blended; in the 3D view, the
// three slices placed in RAS (superimposed on the models). Window/level come from the nodes.
#include <memory>
#include <vector>

#include "vtkRPDisplayableManager.h"

namespace rp {
class SliceReslicer;
}

class vtkRPVolumeSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPVolumeSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPVolumeSliceDisplayableManager, vtkRPDisplayableManager);

  /// The re-slicers (one in a slice view, three in 3D), for tests and the screenshot code.
  int GetNumberOfReslicers() const { return static_cast<int>(this->Reslicers.size()); }
  rp::SliceReslicer* GetReslicer(int i) const { return this->Reslicers.at(static_cast<size_t>(i)).get(); }

 protected:
  vtkRPVolumeSliceDisplayableManager();
  ~vtkRPVolumeSliceDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;

 private:
  vtkRPVolumeSliceDisplayableManager(const vtkRPVolumeSliceDisplayableManager&) = delete;
  void operator=(const vtkRPVolumeSliceDisplayableManager&) = delete;
  void Refresh(vtkRPNode* leaving);
  std::vector<std::unique_ptr<rp::SliceReslicer>> Reslicers;
};

#endif
