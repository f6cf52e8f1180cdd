#include "vtkRPNode.h"

#include <algorithm>

#include "vtkRPScene.h"

vtkRPNode::vtkRPNode() = default;
vtkRPNode::~vtkRPNode() = default;

void vtkRPNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ID: " << this->ID << "\n" << indent << "Name: " << this->Name << "\n";
  for (const auto& [key, value] : this->Attributes) os << indent << "Attribute " << key << ": " << value << "\n";
  for (const auto& [role, ids] : this->References) {
    os << indent << "Reference " << role << ":";
    for (const auto& id : ids) os << " " << id;
    os << "\n";
  }
}

void vtkRPNode::SetName(const std::string& name) {
  if (name == this->Name) return;
  this->Name = name;
  this->Modified();
}

void vtkRPNode::SetAttribute(const std::string& key, const std::string& value) {
  auto it = this->Attributes.find(key);
  if (it != this->Attributes.end() && it->second == value) return;
  this->Attributes[key] = value;
  this->Modified();
}

void vtkRPNode::RemoveAttribute(const std::string& key) {
  if (this->Attributes.erase(key)) this->Modified();
}

std::string vtkRPNode::GetAttribute(const std::string& key) const {
  auto it = this->Attributes.find(key);
  return it == this->Attributes.end() ? std::string() : it->second;
}

bool vtkRPNode::HasAttribute(const std::string& key) const { return this->Attributes.count(key) > 0; }

void vtkRPNode::SetNodeReferenceID(const std::string& role, const std::string& id) {
  auto it = this->References.find(role);
  if (id.empty()) {
    if (it == this->References.end()) return;
    this->References.erase(it);
  } else {
    if (it != this->References.end() && it->second.size() == 1 && it->second[0] == id) return;
    this->References[role] = {id};
  }
  this->OnNodeReferenceChanged(role);
}

void vtkRPNode::AddNodeReferenceID(const std::string& role, const std::string& id) {
  if (id.empty()) return;
  this->References[role].push_back(id);
  this->OnNodeReferenceChanged(role);
}

void vtkRPNode::RemoveNodeReferenceIDs(const std::string& role) {
  if (this->References.erase(role)) this->OnNodeReferenceChanged(role);
}

std::string vtkRPNode::GetNodeReferenceID(const std::string& role, int n) const {
  auto it = this->References.find(role);
  if (it == this->References.end() || n < 0 || n >= static_cast<int>(it->second.size())) return {};
  return it->second[static_cast<size_t>(n)];
}

int vtkRPNode::GetNumberOfNodeReferences(const std::string& role) const {
  auto it = this->References.find(role);
  return it == this->References.end() ? 0 : static_cast<int>(it->second.size());
}

vtkRPNode* vtkRPNode::GetNodeReference(const std::string& role, int n) const {
  const std::string id = this->GetNodeReferenceID(role, n);
  if (id.empty() || !this->Scene) return nullptr;
  return this->Scene->GetNodeByID(id);
}

std::vector<std::string> vtkRPNode::GetReferenceRoles() const {
  std::vector<std::string> roles;
  for (const auto& entry : this->References) roles.push_back(entry.first);
  return roles;
}

bool vtkRPNode::HasReferenceTo(const std::string& id) const {
  for (const auto& entry : this->References) {
    if (std::find(entry.second.begin(), entry.second.end(), id) != entry.second.end()) return true;
  }
  return false;
}

void vtkRPNode::UpdateReferenceID(const std::string& oldID, const std::string& newID) {
  std::vector<std::string> changedRoles;
  for (auto& [role, ids] : this->References) {
    bool changed = false;
    for (auto& id : ids) {
      if (id == oldID) {
        id = newID;
        changed = true;
      }
    }
    if (changed) changedRoles.push_back(role);
  }
  for (const auto& role : changedRoles) this->OnNodeReferenceChanged(role);
}

void vtkRPNode::RemoveReferencesTo(const std::string& id) {
  std::vector<std::string> changedRoles;
  for (auto it = this->References.begin(); it != this->References.end();) {
    auto& ids = it->second;
    const auto before = ids.size();
    ids.erase(std::remove(ids.begin(), ids.end(), id), ids.end());
    if (ids.size() != before) changedRoles.push_back(it->first);
    it = ids.empty() ? this->References.erase(it) : std::next(it);
  }
  for (const auto& role : changedRoles) this->OnNodeReferenceChanged(role);
}

void vtkRPNode::OnNodeReferenceChanged(const std::string& role) {
  this->InvokeEvent(ReferenceModifiedEvent, const_cast<char*>(role.c_str()));
  this->Modified();
}

int vtkRPNode::StartModify() {
  const int previous = this->DisableModified;
  this->DisableModified = 1;
  return previous;
}

int vtkRPNode::EndModify(int previousDisableModify) {
  this->DisableModified = previousDisableModify;
  if (!this->DisableModified && this->ModifiedWhileDisabled) {
    this->ModifiedWhileDisabled = false;
    this->Modified();
  }
  return this->DisableModified;
}

void vtkRPNode::Modified() {
  if (this->DisableModified) {
    this->ModifiedWhileDisabled = true;
    // Keep the modification time current so pipelines see the change, without the event.
    this->MTime.Modified();
    return;
  }
  this->ModifiedWhileDisabled = false;
  this->Superclass::Modified();
}

void vtkRPNode::CopyContent(vtkRPNode* source) {
  if (!source || source == this) return;
  const int previous = this->StartModify();
  this->SetName(source->GetName());
  PropertyMap properties;
  source->WriteProperties(properties);
  this->ReadProperties(properties);
  for (const auto& [key, value] : source->GetAttributes()) this->SetAttribute(key, value);
  for (const auto& role : this->GetReferenceRoles()) {
    if (source->GetNumberOfNodeReferences(role) == 0) this->RemoveNodeReferenceIDs(role);
  }
  for (const auto& role : source->GetReferenceRoles()) {
    this->RemoveNodeReferenceIDs(role);
    for (int n = 0; n < source->GetNumberOfNodeReferences(role); ++n) {
      this->AddNodeReferenceID(role, source->GetNodeReferenceID(role, n));
    }
  }
  this->UpdateReferences();
  this->EndModify(previous);
}

void vtkRPNode::WriteProperties(PropertyMap&) const {}
void vtkRPNode::ReadProperties(const PropertyMap&) {}
