#include "vtkRPTransformableNode.h"

#include <vtkCallbackCommand.h>
#include <vtkMatrix4x4.h>

#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"

vtkRPTransformableNode::vtkRPTransformableNode() {
  this->ParentCallback = vtkCallbackCommand::New();
  this->ParentCallback->SetClientData(this);
  this->ParentCallback->SetCallback(&vtkRPTransformableNode::OnParentTransformModified);
}

vtkRPTransformableNode::~vtkRPTransformableNode() {
  if (this->ObservedParent) {
    this->ObservedParent->RemoveObserver(this->ParentObserverTag);
    this->ObservedParent->RemoveObserver(this->ParentDeleteTag);
  }
  this->ParentCallback->Delete();
}

void vtkRPTransformableNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TransformNodeID: " << this->GetTransformNodeID() << "\n";
}

vtkRPLinearTransformNode* vtkRPTransformableNode::GetParentTransformNode() const {
  return vtkRPLinearTransformNode::SafeDownCast(this->GetNodeReference(TransformRole()));
}

bool vtkRPTransformableNode::IsInParentChain(const vtkRPNode* node) const {
  const vtkRPTransformableNode* current = this;
  int guard = 0;
  while (current && guard++ < 10000) {
    if (current == node) return true;
    current = current->GetParentTransformNode();
  }
  return false;
}

bool vtkRPTransformableNode::SetAndObserveTransformNodeID(const std::string& transformNodeID) {
  if (!transformNodeID.empty() && this->GetScene()) {
    auto* parent = vtkRPLinearTransformNode::SafeDownCast(this->GetScene()->GetNodeByID(transformNodeID));
    if (!parent) {
      vtkErrorMacro("SetAndObserveTransformNodeID: '" << transformNodeID << "' is not a transform node in the scene");
      return false;
    }
    if (parent->IsInParentChain(this)) {
      vtkErrorMacro("SetAndObserveTransformNodeID: making '" << transformNodeID << "' the parent of '"
                                                             << this->GetID() << "' would create a cycle");
      return false;
    }
  }
  this->SetNodeReferenceID(TransformRole(), transformNodeID);
  return true;
}

void vtkRPTransformableNode::GetParentTransformToWorld(vtkMatrix4x4* toWorld) const {
  toWorld->Identity();
  if (vtkRPLinearTransformNode* parent = this->GetParentTransformNode()) {
    // Cycles are refused when set, but a scene file may hold one: stop rather than recurse forever.
    if (parent->IsInParentChain(this) && parent != this) {
      return;
    }
    parent->GetMatrixTransformToWorld(toWorld);
  }
}

void vtkRPTransformableNode::GetMatrixTransformToWorld(vtkMatrix4x4* toWorld) const {
  this->GetParentTransformToWorld(toWorld);
}

void vtkRPTransformableNode::OnNodeReferenceChanged(const std::string& role) {
  this->Superclass::OnNodeReferenceChanged(role);
  if (role == TransformRole()) {
    this->ObserveParentTransform();
    this->InvokeEvent(TransformModifiedEvent, this);
  }
}

void vtkRPTransformableNode::UpdateReferences() {
  this->Superclass::UpdateReferences();
  this->ObserveParentTransform();
}

void vtkRPTransformableNode::ObserveParentTransform() {
  vtkRPNode* parent = this->GetParentTransformNode();
  if (parent == this->ObservedParent) return;
  if (this->ObservedParent) {
    this->ObservedParent->RemoveObserver(this->ParentObserverTag);
    this->ObservedParent->RemoveObserver(this->ParentDeleteTag);
  }
  this->ObservedParent = parent;
  if (parent) {
    this->ParentObserverTag = parent->AddObserver(TransformModifiedEvent, this->ParentCallback);
    this->ParentDeleteTag = parent->AddObserver(vtkCommand::DeleteEvent, this->ParentCallback);
  }
}

void vtkRPTransformableNode::OnParentTransformModified(vtkObject* caller, unsigned long event, void* clientData,
                                                       void*) {
  auto* self = static_cast<vtkRPTransformableNode*>(clientData);
  if (event == vtkCommand::DeleteEvent) {
    if (caller == self->ObservedParent) self->ObservedParent = nullptr;
    return;
  }
  self->InvokeEvent(TransformModifiedEvent, self);
}
