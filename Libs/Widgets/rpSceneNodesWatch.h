#pragma once
// What a panel watches to keep its node lists current: the scene's set of nodes changed (a node
// added or removed, an import or a close ended). The scene's event only sets a flag; the panel
// re-reads its lists on its next display tick (TakeChanged), never inside the scene's event.
// Main thread, as the scene.
#include <vector>

#include <vtkSmartPointer.h>

class vtkCallbackCommand;
class vtkObject;
class vtkRPScene;

namespace rp {

class SceneNodesWatch {
 public:
  explicit SceneNodesWatch(vtkRPScene* scene);  // null: nothing to watch
  ~SceneNodesWatch();
  SceneNodesWatch(const SceneNodesWatch&) = delete;
  SceneNodesWatch& operator=(const SceneNodesWatch&) = delete;

  /// True once after the scene's nodes changed (then false until they change again).
  bool TakeChanged();

 private:
  static void OnChanged(vtkObject*, unsigned long, void* clientData, void*);
  vtkRPScene* Scene;  // not owned: the host's scene outlives its panels
  vtkSmartPointer<vtkCallbackCommand> Callback;
  std::vector<unsigned long> Tags;
  bool Changed = false;
};

}  // namespace rp
