#ifndef vtkRPModelDisplayableManager_h
#define vtkRPModelDisplayableManager_h
// Models in the 3D view: one actor per model node with its colour, opacity, visibility and
// to-world transform. While the view is interactive (redrawn tick after tick, e.g. the slices
// following a tool), models are drawn from a display level of detail: a copy decimated by
// quadric clustering so that all visible models together stay within a triangle budget. The
// copies are made before the first frame that draws a new model (at load, not on the first tick
// of an interaction) and again only when a mesh changes. Still frames use the full meshes.
#include <map>
#include <memory>

#include <vtkSmartPointer.h>

#include "vtkRPDisplayableManager.h"

class vtkActor;
class vtkCallbackCommand;
class vtkObject;
class vtkPolyData;

class vtkRPModelDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPModelDisplayableManager* New();
  vtkTypeMacro(vtkRPModelDisplayableManager, vtkRPDisplayableManager);

  /// The actor drawing a node (nullptr if none), for tests.
  vtkActor* GetActor(vtkRPNode* node) const;
  /// Triangles drawn in interactive frames for all visible models together (default 25 000:
  /// a 3D view of 700×550 on llvmpipe draws that in ~20 ms, see rpViewerBenchmark).
  void SetInteractiveTriangleBudget(double triangles);
  double GetInteractiveTriangleBudget() const { return this->InteractiveTriangleBudget; }
  /// The mesh a node is drawn with now (full or level of detail), for tests.
  vtkPolyData* GetDrawnPolyData(vtkRPNode* node) const;
  void SetInteractive(bool interactive) override;
  /// Makes the display level of detail of every visible model now (the view's first render
  /// after a model arrives calls it).
  void PrepareInteractiveDetail();

 protected:
  vtkRPModelDisplayableManager() = default;
  ~vtkRPModelDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnInitialize() override;
  void OnFinalize() override;

 private:
  vtkRPModelDisplayableManager(const vtkRPModelDisplayableManager&) = delete;
  void operator=(const vtkRPModelDisplayableManager&) = delete;
  struct Display;
  void ChooseDetail(vtkRPNode* node, Display& display);
  /// The decimated copy of a model at its share of the budget (nullptr: draw it as it is).
  vtkPolyData* LightMesh(vtkRPNode* node, Display& display);
  static void OnRenderStart(vtkObject*, unsigned long, void* clientData, void*);
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
  vtkSmartPointer<vtkCallbackCommand> RenderCallback;
  unsigned long RenderTag = 0;
  bool PreparePending = false;
  double InteractiveTriangleBudget = 25000;
  bool Interactive = false;
};

#endif
