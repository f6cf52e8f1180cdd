#ifndef vtkRPSegmentationSliceDisplayableManager_h
#define vtkRPSegmentationSliceDisplayableManager_h
// The label layer of a slice view: the segmentation its slice node names (Label role),
// re-sliced (nearest neighbour) on the node's plane and drawn over the volumes in the segments'
// colours with the node's label opacity. Label values without a segment are not drawn. (In 3D,
// segmentations show through the models made from them.)
#include <map>
#include <memory>

#include "vtkRPDisplayableManager.h"

class vtkImageData;

class vtkRPSegmentationSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPSegmentationSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPSegmentationSliceDisplayableManager, vtkRPDisplayableManager);

  /// The RGBA overlay drawn for a node (nullptr if none), for tests; its pixel (i, j) is at
  /// RAS = SliceToRAS · (origin + spacing · (i, j, 0)).
  vtkImageData* GetOverlay(vtkRPNode* node);

 protected:
  vtkRPSegmentationSliceDisplayableManager() = default;
  ~vtkRPSegmentationSliceDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;

 private:
  vtkRPSegmentationSliceDisplayableManager(const vtkRPSegmentationSliceDisplayableManager&) = delete;
  void operator=(const vtkRPSegmentationSliceDisplayableManager&) = delete;
  struct Overlay;
  void UpdatePlane(Overlay& overlay, vtkRPNode* node);
  std::map<vtkRPNode*, std::unique_ptr<Overlay>> Overlays;
};

#endif
