#include "vtkRPFiducialListNode.h"

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPFiducialListNode);

vtkRPNode* vtkRPFiducialListNode::CreateNodeInstance() { return vtkRPFiducialListNode::New(); }
