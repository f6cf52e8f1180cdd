#ifndef vtkRPTransformableNode_h
#define vtkRPTransformableNode_h
// A node that can sit under a parent transform node. Its to-world matrix follows the chain of
// parents; when any transform up the chain changes, it fires TransformModifiedEvent.
#include "vtkRPNode.h"

class vtkMatrix4x4;
class vtkRPLinearTransformNode;
class vtkCallbackCommand;

class vtkRPTransformableNode : public vtkRPNode {
 public:
  vtkTypeMacro(vtkRPTransformableNode, vtkRPNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  static const char* TransformRole() { return "transform"; }

  /// Sets the parent transform. Refuses (returns false, with an error message) a parent that is
  /// not a linear transform node or that would make a cycle. "" removes the parent.
  bool SetAndObserveTransformNodeID(const std::string& transformNodeID);
  std::string GetTransformNodeID() const { return this->GetNodeReferenceID(TransformRole()); }
  vtkRPLinearTransformNode* GetParentTransformNode() const;

  /// Matrix from this node's coordinates to world (RAS): the product of the parents' to-parent
  /// matrices. Identity without a parent. Transform nodes include their own matrix.
  virtual void GetMatrixTransformToWorld(vtkMatrix4x4* toWorld) const;
  /// Matrix of the parent chain only (excludes a transform node's own matrix).
  void GetParentTransformToWorld(vtkMatrix4x4* toWorld) const;

  /// True if `node` is this node or one of its ancestors (used for cycle checks).
  bool IsInParentChain(const vtkRPNode* node) const;

  void UpdateReferences() override;

 protected:
  vtkRPTransformableNode();
  ~vtkRPTransformableNode() override;
  void OnNodeReferenceChanged(const std::string& role) override;
  void ObserveParentTransform();
  static void OnParentTransformModified(vtkObject*, unsigned long, void* clientData, void*);

 private:
  vtkRPTransformableNode(const vtkRPTransformableNode&) = delete;
  void operator=(const vtkRPTransformableNode&) = delete;
  vtkRPNode* ObservedParent = nullptr;
  unsigned long ParentObserverTag = 0;
  unsigned long ParentDeleteTag = 0;
  vtkCallbackCommand* ParentCallback = nullptr;
};

#endif
