#ifndef vtkRPModelDisplayableManager_h
#define vtkRPModelDisplayableManager_h
// Models in the 3D view: one actor per model node with its colour, opacity, visibility and
// to-world transform. While the view is interactive (redrawn tick after tick, e.g. the slices
// following a tool), models are drawn from a display level of detail: a copy decimated by
// quadric clustering so that all visible models together stay within a triangle budget (made
// once per mesh, when first needed). Still frames use the full meshes.
#include <map>
#include <memory>

#include <vtkSmartPointer.h>

#include "vtkRPDisplayableManager.h"

class vtkActor;
class vtkPolyData;

class vtkRPModelDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPModelDisplayableManager* New();
  vtkTypeMacro(vtkRPModelDisplayableManager, vtkRPDisplayableManager);

  /// The actor drawing a node (nullptr if none), for tests.
  vtkActor* GetActor(vtkRPNode* node) const;
  /// Triangles drawn in interactive frames for all visible models together (default 60 000).
  void SetInteractiveTriangleBudget(double triangles);
  double GetInteractiveTriangleBudget() const { return this->InteractiveTriangleBudget; }
  /// The mesh a node is drawn with now (full or level of detail), for tests.
  vtkPolyData* GetDrawnPolyData(vtkRPNode* node) const;
  void SetInteractive(bool interactive) override;

 protected:
  vtkRPModelDisplayableManager() = default;
  ~vtkRPModelDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;

 private:
  vtkRPModelDisplayableManager(const vtkRPModelDisplayableManager&) = delete;
  void operator=(const vtkRPModelDisplayableManager&) = delete;
  struct Display;
  void ChooseDetail(vtkRPNode* node, Display& display);
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
  double InteractiveTriangleBudget = 60000;
  bool Interactive = false;
};

#endif
