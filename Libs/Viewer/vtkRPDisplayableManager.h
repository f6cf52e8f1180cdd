#ifndef vtkRPDisplayableManager_h
#define vtkRPDisplayableManager_h
// Base of the displayable managers (Slicer's pattern): one class per kind of node draws the
// scene's nodes of that kind in one view. It observes the scene (node added → display created,
// about to be removed → display removed), each node it displays (ModifiedEvent and
// TransformModifiedEvent → display updated), the view's slice node (plane, layers) and the
// viewer's interaction state. Modules never draw: they change nodes and the managers follow.
#include <map>
#include <vector>

#include <vtkObject.h>
#include <vtkWeakPointer.h>

class vtkCallbackCommand;
class vtkMapper;
class vtkRPNode;
class vtkRPScene;
class vtkRPSliceNode;
class vtkRPViewState;
namespace rp {
class View;
}

class vtkRPDisplayableManager : public vtkObject {
 public:
  vtkTypeMacro(vtkRPDisplayableManager, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Starts observing the view's scene and state and displays the nodes already there.
  void Initialize(rp::View* view);
  /// Removes every display and observer (the view calls it before it goes away).
  void Finalize();

  rp::View* GetView() const { return this->View; }
  /// For geometry rebuilt while a tool moves (outlines, crosshair, slice quads), in mm near the
  /// patient: VTK's automatic vertex shift-and-scale would find the points' range on every
  /// upload (a parallel pass over a few thousand points: thread wake-ups, not arithmetic).
  static void SkipVertexShift(vtkMapper* mapper);
  /// Interactive level of detail (the view is redrawn tick after tick): draw lighter if it helps.
  virtual void SetInteractive(bool interactive) { (void)interactive; }
  vtkRPScene* GetScene() const;
  vtkRPViewState* GetViewState() const;
  /// The slice node of a slice view (nullptr in 3D).
  vtkRPSliceNode* GetSliceNode() const;
  /// Number of nodes this manager currently displays (tests use it).
  int GetNumberOfDisplayedNodes() const { return static_cast<int>(this->Observed.size()); }
  bool IsDisplayed(vtkRPNode* node) const { return this->Observed.count(node) > 0; }

 protected:
  vtkRPDisplayableManager();
  ~vtkRPDisplayableManager() override;

  virtual bool CanDisplay(vtkRPNode* node) const = 0;
  virtual void AddDisplay(vtkRPNode* node) = 0;
  virtual void RemoveDisplay(vtkRPNode* node) = 0;
  virtual void UpdateDisplay(vtkRPNode* node) = 0;
  /// The view's slice node (plane, layers) or the interaction state changed.
  virtual void OnViewStateModified() {}
  /// After Initialize has set the view up (before the scene's nodes are displayed) / before
  /// Finalize tears it down: managers that draw more than nodes set up and remove their props.
  virtual void OnInitialize() {}
  virtual void OnFinalize() {}
  /// A scene node event this manager asked for (other than Modified/TransformModified).
  virtual std::vector<unsigned long> ExtraNodeEvents() const { return {}; }

  void RequestRender();
  std::vector<vtkRPNode*> GetDisplayedNodes() const;

 private:
  vtkRPDisplayableManager(const vtkRPDisplayableManager&) = delete;
  void operator=(const vtkRPDisplayableManager&) = delete;
  static void OnSceneEvent(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  static void OnNodeEvent(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  static void OnStateEvent(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  void StartDisplaying(vtkRPNode* node);
  void StopDisplaying(vtkRPNode* node);

  rp::View* View = nullptr;
  vtkWeakPointer<vtkRPScene> Scene;
  vtkWeakPointer<vtkRPViewState> State;
  vtkWeakPointer<vtkRPSliceNode> SliceNode;
  std::vector<unsigned long> SceneTags;
  unsigned long StateTag = 0;
  unsigned long SliceNodeTag = 0;
  struct ObservedNode {
    vtkWeakPointer<vtkRPNode> Node;
    std::vector<unsigned long> Tags;
  };
  std::map<vtkRPNode*, ObservedNode> Observed;
  vtkCallbackCommand* SceneCallback;
  vtkCallbackCommand* NodeCallback;
  vtkCallbackCommand* StateCallback;
};

#endif
