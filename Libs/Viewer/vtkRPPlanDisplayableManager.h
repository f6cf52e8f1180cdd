#ifndef vtkRPPlanDisplayableManager_h
#define vtkRPPlanDisplayableManager_h
// Plans (Libs/MRML: trajectories, screws, cut planes) in a view, in the plan's colour. A
// trajectory is its tool: in 3D a cylinder of the tool's diameter from entry to target; in a
// slice view the axis projected onto the slice (thin) and the cylinder's outline where the slice
// cuts it. A cut plane is its rectangle (size, axes) in 3D, translucent, and in a slice view the
// line where it crosses the slice. The points themselves (entry, target, origin) are drawn and
// dragged as control points (vtkRPFiducialDisplayableManager, the view controller).
#include <map>
#include <memory>

#include "vtkRPDisplayableManager.h"

class vtkPolyData;

class vtkRPPlanDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPPlanDisplayableManager* New();
  vtkTypeMacro(vtkRPPlanDisplayableManager, vtkRPDisplayableManager);

  /// What is drawn for a plan now, in world RAS (tests): the tool's surface or the plane's
  /// rectangle in 3D; the cut outline and the projected axis in a slice view. Null when hidden.
  vtkPolyData* GetDrawnGeometry(vtkRPNode* node) const;

 protected:
  vtkRPPlanDisplayableManager() = default;
  ~vtkRPPlanDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;

 private:
  vtkRPPlanDisplayableManager(const vtkRPPlanDisplayableManager&) = delete;
  void operator=(const vtkRPPlanDisplayableManager&) = delete;
  struct Display;
  void Rebuild(vtkRPNode* node, Display& display);
  void CutWithSlice(Display& display);
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
};

#endif
