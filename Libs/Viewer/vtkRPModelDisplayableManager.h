#ifndef vtkRPModelDisplayableManager_h
#define vtkRPModelDisplayableManager_h
// Models in the 3D view: one actor per model node with its colour, opacity, visibility and
// to-world transform.
#include <map>

#include <vtkSmartPointer.h>

#include "vtkRPDisplayableManager.h"

class vtkActor;

class vtkRPModelDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPModelDisplayableManager* New();
  vtkTypeMacro(vtkRPModelDisplayableManager, vtkRPDisplayableManager);

  /// The actor drawing a node (nullptr if none), for tests.
  vtkActor* GetActor(vtkRPNode* node) const;

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
  std::map<vtkRPNode*, vtkSmartPointer<vtkActor>> Actors;
};

#endif
