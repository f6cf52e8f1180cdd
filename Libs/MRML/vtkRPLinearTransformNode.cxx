#include "vtkRPLinearTransformNode.h"

#include <sstream>

#include <vtkNew.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPLinearTransformNode);

vtkRPLinearTransformNode::vtkRPLinearTransformNode() : ToParent(vtkSmartPointer<vtkMatrix4x4>::New()) {}
vtkRPLinearTransformNode::~vtkRPLinearTransformNode() = default;

vtkRPNode* vtkRPLinearTransformNode::CreateNodeInstance() { return vtkRPLinearTransformNode::New(); }

void vtkRPLinearTransformNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MatrixTransformToParent:\n";
  this->ToParent->PrintSelf(os, indent.GetNextIndent());
}

void vtkRPLinearTransformNode::SetMatrixTransformToParent(const vtkMatrix4x4* matrix) {
  if (!matrix) return;
  bool same = true;
  for (int i = 0; i < 4 && same; ++i)
    for (int j = 0; j < 4 && same; ++j) same = this->ToParent->GetElement(i, j) == matrix->GetElement(i, j);
  if (same) return;
  this->ToParent->DeepCopy(matrix);
  this->Modified();
  this->InvokeEvent(TransformModifiedEvent, this);
}

void vtkRPLinearTransformNode::SetMatrixTransformToParent(const double elements[16]) {
  vtkNew<vtkMatrix4x4> m;
  m->DeepCopy(elements);
  this->SetMatrixTransformToParent(m);
}

void vtkRPLinearTransformNode::GetMatrixTransformFromParent(vtkMatrix4x4* fromParent) const {
  vtkMatrix4x4::Invert(this->ToParent, fromParent);
}

void vtkRPLinearTransformNode::SetMatrixTransformFromParent(const vtkMatrix4x4* fromParent) {
  vtkNew<vtkMatrix4x4> toParent;
  vtkMatrix4x4::Invert(fromParent, toParent);
  this->SetMatrixTransformToParent(toParent);
}

void vtkRPLinearTransformNode::GetMatrixTransformToWorld(vtkMatrix4x4* toWorld) const {
  vtkNew<vtkMatrix4x4> parentToWorld;
  this->GetParentTransformToWorld(parentToWorld);
  vtkMatrix4x4::Multiply4x4(parentToWorld, this->ToParent, toWorld);
}

void vtkRPLinearTransformNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  // The matrix lives in the transform file; a readable copy here helps people reading the scene.
  std::ostringstream ss;
  ss.precision(17);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) ss << (i || j ? " " : "") << this->ToParent->GetElement(i, j);
  properties["matrixToParent"] = ss.str();
}

void vtkRPLinearTransformNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  auto it = properties.find("matrixToParent");
  if (it == properties.end()) return;
  std::istringstream ss(it->second);
  double e[16];
  for (double& v : e) {
    if (!(ss >> v)) return;
  }
  this->SetMatrixTransformToParent(e);
}
