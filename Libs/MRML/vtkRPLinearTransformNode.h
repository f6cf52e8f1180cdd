#ifndef vtkRPLinearTransformNode_h
#define vtkRPLinearTransformNode_h
// A linear (4x4) transform. Holds the "to parent" matrix, as Slicer does; children use it.
// Saved as an ITK transform file (LPS, "from parent" convention), so Slicer opens it unchanged.
#include <vtkSmartPointer.h>

#include "vtkRPTransformableNode.h"

#include <vtkMatrix4x4.h>

class vtkRPLinearTransformNode : public vtkRPTransformableNode {
 public:
  static vtkRPLinearTransformNode* New();
  vtkTypeMacro(vtkRPLinearTransformNode, vtkRPTransformableNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "LinearTransform"; }

  /// The matrix from this node's coordinate frame to its parent's. The returned matrix must not
  /// be modified directly; use SetMatrixTransformToParent.
  vtkMatrix4x4* GetMatrixTransformToParent() const { return this->ToParent; }
  void SetMatrixTransformToParent(const vtkMatrix4x4* matrix);
  void SetMatrixTransformToParent(const double elements[16]);  // row-major
  void GetMatrixTransformFromParent(vtkMatrix4x4* fromParent) const;
  void SetMatrixTransformFromParent(const vtkMatrix4x4* fromParent);

  void GetMatrixTransformToWorld(vtkMatrix4x4* toWorld) const override;

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPLinearTransformNode();
  ~vtkRPLinearTransformNode() override;

 private:
  vtkRPLinearTransformNode(const vtkRPLinearTransformNode&) = delete;
  void operator=(const vtkRPLinearTransformNode&) = delete;
  vtkSmartPointer<vtkMatrix4x4> ToParent;
};

#endif
