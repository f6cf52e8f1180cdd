#ifndef vtkRPModelSliceDisplayableManager_h
#define vtkRPModelSliceDisplayableManager_h
// Models in a slice view: the outline where the slice plane cuts each visible model, in the
// model's colour. The cut is evaluated in the model's own coordinates (the plane is moved by
// the model's to-world transform), so a transformed model is never copied; it runs when the
// view renders (once per frame however often the plane moved) with rp::PlaneCutter, which looks
// only at the triangles near the plane.
#include <map>
#include <memory>

#include <vtkNew.h>

#include "vtkRPDisplayableManager.h"

class vtkCallbackCommand;
class vtkPolyData;
class vtkRenderer;

class vtkRPModelSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPModelSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPModelSliceDisplayableManager, vtkRPDisplayableManager);

  /// The outline currently drawn for a node (in the model's coordinates), for tests; nullptr if none.
  vtkPolyData* GetOutline(vtkRPNode* node);

 protected:
  vtkRPModelSliceDisplayableManager();
  ~vtkRPModelSliceDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;
  void OnInitialize() override;
  void OnFinalize() override;

 private:
  vtkRPModelSliceDisplayableManager(const vtkRPModelSliceDisplayableManager&) = delete;
  void operator=(const vtkRPModelSliceDisplayableManager&) = delete;
  struct Outline;
  std::map<vtkRPNode*, std::unique_ptr<Outline>> Outlines;
  void UpdatePlane(Outline& outline, vtkRPNode* node);
  void Cut(Outline& outline);
  void CutDirtyOutlines();
  vtkNew<vtkCallbackCommand> RenderCallback;
  vtkRenderer* RenderTarget = nullptr;
  unsigned long RenderTag = 0;
};

#endif
