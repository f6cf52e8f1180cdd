#ifndef vtkRPModelSliceDisplayableManager_h
#define vtkRPModelSliceDisplayableManager_h
// Models in a slice view: the outline where the slice plane cuts each visible model, in the
// model's colour. The cut is evaluated in the model's own coordinates (the plane is moved by
// the model's to-world transform), so a transformed model is never copied.
#include <map>
#include <memory>

#include "vtkRPDisplayableManager.h"

class vtkPolyData;

class vtkRPModelSliceDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPModelSliceDisplayableManager* New();
  vtkTypeMacro(vtkRPModelSliceDisplayableManager, vtkRPDisplayableManager);

  /// The outline currently drawn for a node (in the model's coordinates), for tests; nullptr if none.
  vtkPolyData* GetOutline(vtkRPNode* node);

 protected:
  vtkRPModelSliceDisplayableManager() = default;
  ~vtkRPModelSliceDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;

 private:
  vtkRPModelSliceDisplayableManager(const vtkRPModelSliceDisplayableManager&) = delete;
  void operator=(const vtkRPModelSliceDisplayableManager&) = delete;
  struct Outline;
  std::map<vtkRPNode*, std::unique_ptr<Outline>> Outlines;
  void UpdatePlane(Outline& outline, vtkRPNode* node);
};

#endif
