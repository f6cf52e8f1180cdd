#ifndef vtkRPFiducialListNode_h
#define vtkRPFiducialListNode_h
// A list of control points (Slicer's markups fiducial list, "MarkupsFiducial"): any number of
// labelled points, e.g. a registration's landmarks. Everything is in vtkRPMarkupsNode.
#include "vtkRPMarkupsNode.h"

class vtkRPFiducialListNode : public vtkRPMarkupsNode {
 public:
  static vtkRPFiducialListNode* New();
  vtkTypeMacro(vtkRPFiducialListNode, vtkRPMarkupsNode);
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "FiducialList"; }
  const char* GetMarkupsType() const override { return "Fiducial"; }

 protected:
  vtkRPFiducialListNode() = default;
  ~vtkRPFiducialListNode() override = default;

 private:
  vtkRPFiducialListNode(const vtkRPFiducialListNode&) = delete;
  void operator=(const vtkRPFiducialListNode&) = delete;
};

#endif
