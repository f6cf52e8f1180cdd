#include "vtkRPScene.h"

#include <algorithm>
#include <set>

#include <vtkObjectFactory.h>

#include "vtkRPCutPlaneNode.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrajectoryNode.h"

vtkStandardNewMacro(vtkRPScene);

vtkRPScene::vtkRPScene() {
  for (vtkRPNode* prototype :
       std::initializer_list<vtkRPNode*>{vtkRPLinearTransformNode::New(), vtkRPTrackedToolNode::New(),
                                         vtkRPScalarVolumeNode::New(), vtkRPSegmentationNode::New(),
                                         vtkRPModelNode::New(), vtkRPFiducialListNode::New(),
                                         vtkRPTrajectoryNode::New(), vtkRPScrewNode::New(),
                                         vtkRPCutPlaneNode::New(), vtkRPSliceNode::New(), vtkRPLayoutNode::New()}) {
    this->RegisterNodeClass(prototype);
    prototype->Delete();
  }
}

vtkRPScene::~vtkRPScene() {
  for (auto& node : this->Nodes) node->SetSceneInternal(nullptr);
}

void vtkRPScene::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Nodes: " << this->Nodes.size() << "\n";
  for (const auto& node : this->Nodes) {
    os << indent.GetNextIndent() << node->GetID() << " (" << node->GetClassName() << ") \""
       << node->GetName() << "\"\n";
  }
}

void vtkRPScene::RegisterNodeClass(vtkRPNode* prototype) {
  if (prototype) this->Prototypes[prototype->GetClassName()] = prototype;
}

vtkSmartPointer<vtkRPNode> vtkRPScene::CreateNodeByClass(const std::string& className) const {
  auto it = this->Prototypes.find(className);
  if (it == this->Prototypes.end()) return nullptr;
  return vtkSmartPointer<vtkRPNode>::Take(it->second->CreateNodeInstance());
}

std::vector<std::string> vtkRPScene::GetRegisteredNodeClasses() const {
  std::vector<std::string> names;
  for (const auto& entry : this->Prototypes) names.push_back(entry.first);
  return names;
}

std::string vtkRPScene::GenerateUniqueID(vtkRPNode* node) {
  const std::string base = node->GetClassName();
  int& next = this->NextIDNumber[base];
  std::string id;
  do {
    id = base + std::to_string(++next);
  } while (this->NodesByID.count(id));
  return id;
}

std::string vtkRPScene::GenerateUniqueName(const std::string& base) const {
  if (this->GetNodesByName(base).empty()) return base;
  for (int n = 1;; ++n) {
    const std::string name = base + "_" + std::to_string(n);
    if (this->GetNodesByName(name).empty()) return name;
  }
}

void vtkRPScene::InsertNode(vtkRPNode* node) {
  this->Nodes.emplace_back(node);
  this->NodesByID[node->GetID()] = node;
  node->SetSceneInternal(this);
}

vtkRPNode* vtkRPScene::AddNode(vtkRPNode* node) {
  if (!node) return nullptr;
  if (node->GetScene()) {
    vtkErrorMacro("AddNode: node " << node->GetID() << " is already in a scene");
    return nullptr;
  }
  if (node->IsSingleton()) {
    if (vtkRPNode* existing = this->GetSingletonNode(node->GetSingletonTag(), node->GetClassName())) {
      existing->CopyContent(node);
      return existing;
    }
  }
  if (node->GetID().empty() || this->NodesByID.count(node->GetID())) {
    node->SetIDInternal(this->GenerateUniqueID(node));
  }
  if (node->GetName().empty()) {
    node->SetName(this->GenerateUniqueName(node->GetNodeTagName()));
  } else if (!this->GetNodesByName(node->GetName()).empty()) {
    node->SetName(this->GenerateUniqueName(node->GetName()));
  }
  this->InsertNode(node);
  node->UpdateReferences();
  this->InvokeEvent(NodeAddedEvent, node);
  this->Modified();
  return node;
}

void vtkRPScene::RemoveNode(vtkRPNode* node) {
  if (!node || node->GetScene() != this) return;
  vtkSmartPointer<vtkRPNode> keepAlive = node;  // observers may still look at it
  this->InvokeEvent(NodeAboutToBeRemovedEvent, node);
  const std::string id = node->GetID();
  this->Nodes.erase(std::remove(this->Nodes.begin(), this->Nodes.end(), keepAlive), this->Nodes.end());
  this->NodesByID.erase(id);
  node->SetSceneInternal(nullptr);
  for (auto& other : this->Nodes) {
    if (other->HasReferenceTo(id)) other->RemoveReferencesTo(id);
  }
  this->InvokeEvent(NodeRemovedEvent, node);
  this->Modified();
}

void vtkRPScene::Clear() {
  this->Closing = true;
  this->InvokeEvent(StartCloseEvent);
  this->StartBatchProcess();
  for (size_t i = this->Nodes.size(); i-- > 0;) {
    if (i < this->Nodes.size() && !this->Nodes[i]->IsSingleton()) this->RemoveNode(this->Nodes[i]);
  }
  this->EndBatchProcess();
  this->Closing = false;
  this->InvokeEvent(EndCloseEvent);
}

vtkRPNode* vtkRPScene::GetNodeByID(const std::string& id) const {
  auto it = this->NodesByID.find(id);
  return it == this->NodesByID.end() ? nullptr : it->second;
}

std::vector<vtkRPNode*> vtkRPScene::GetNodesByName(const std::string& name) const {
  std::vector<vtkRPNode*> found;
  for (const auto& node : this->Nodes) {
    if (node->GetName() == name) found.push_back(node);
  }
  return found;
}

vtkRPNode* vtkRPScene::GetFirstNodeByName(const std::string& name) const {
  for (const auto& node : this->Nodes) {
    if (node->GetName() == name) return node;
  }
  return nullptr;
}

vtkRPNode* vtkRPScene::GetSingletonNode(const std::string& tag, const char* className) const {
  if (tag.empty()) return nullptr;
  for (const auto& node : this->Nodes) {
    if (node->GetSingletonTag() == tag && node->IsA(className)) return node;
  }
  return nullptr;
}

std::vector<vtkRPNode*> vtkRPScene::GetNodesByClass(const char* className) const {
  std::vector<vtkRPNode*> found;
  for (const auto& node : this->Nodes) {
    if (node->IsA(className)) found.push_back(node);
  }
  return found;
}

vtkRPNode* vtkRPScene::GetNthNode(int n) const {
  if (n < 0 || n >= static_cast<int>(this->Nodes.size())) return nullptr;
  return this->Nodes[static_cast<size_t>(n)];
}

std::vector<vtkRPNode*> vtkRPScene::GetNodes() const {
  std::vector<vtkRPNode*> nodes;
  for (const auto& node : this->Nodes) nodes.push_back(node);
  return nodes;
}

std::map<std::string, std::string> vtkRPScene::Import(const std::vector<vtkSmartPointer<vtkRPNode>>& nodes) {
  std::map<std::string, std::string> remap;
  this->Importing = true;
  this->InvokeEvent(StartImportEvent);
  this->StartBatchProcess();
  // 0. Singletons already in the scene take the imported content; references to the imported
  //    copy point at the scene's node.
  std::vector<std::pair<vtkRPNode*, vtkRPNode*>> merged;  // existing, imported
  std::set<vtkRPNode*> skip;
  for (const auto& node : nodes) {
    vtkRPNode* existing = node->IsSingleton() ? this->GetSingletonNode(node->GetSingletonTag(), node->GetClassName()) : nullptr;
    if (!existing) continue;
    merged.emplace_back(existing, node);
    skip.insert(node);
  }
  // 1. Give each imported node an ID free in this scene (and among the imported ones).
  std::set<std::string> taken;
  for (const auto& entry : this->NodesByID) taken.insert(entry.first);
  for (const auto& [existing, imported] : merged) remap[imported->GetID()] = existing->GetID();
  for (const auto& node : nodes) {
    if (skip.count(node)) continue;
    const std::string oldID = node->GetID();
    std::string newID = oldID;
    if (newID.empty() || taken.count(newID)) {
      do {
        newID = this->GenerateUniqueID(node);
      } while (taken.count(newID));
    }
    taken.insert(newID);
    remap[oldID] = newID;
  }
  // 2. Rewrite references among imported nodes to the new IDs (two passes so that swapping IDs,
  //    e.g. A→B and B→C, never rewrites a reference twice).
  for (const auto& node : nodes) {
    for (const auto& [oldID, newID] : remap) {
      if (oldID != newID && node->HasReferenceTo(oldID)) node->UpdateReferenceID(oldID, "\x01" + newID);
    }
    for (const auto& [oldID, newID] : remap) {
      if (oldID != newID && node->HasReferenceTo("\x01" + newID)) node->UpdateReferenceID("\x01" + newID, newID);
    }
  }
  // 3. Insert, with unique names, then resolve references once everything is in.
  for (const auto& node : nodes) {
    if (skip.count(node)) continue;
    node->SetIDInternal(remap[node->GetID()]);
    if (node->GetName().empty() || !this->GetNodesByName(node->GetName()).empty()) {
      node->SetName(this->GenerateUniqueName(node->GetName().empty() ? node->GetNodeTagName() : node->GetName()));
    }
    this->InsertNode(node);
  }
  for (const auto& node : nodes) {
    if (!skip.count(node)) node->UpdateReferences();
  }
  for (const auto& node : nodes) {
    if (!skip.count(node)) this->InvokeEvent(NodeAddedEvent, node.GetPointer());
  }
  // After the new nodes are announced, so observers of the singletons find what they refer to.
  for (const auto& [existing, imported] : merged) existing->CopyContent(imported);
  this->EndBatchProcess();
  this->Importing = false;
  this->InvokeEvent(EndImportEvent);
  this->Modified();
  return remap;
}

void vtkRPScene::StartBatchProcess() {
  if (this->BatchDepth++ == 0) this->InvokeEvent(StartBatchProcessEvent);
}

void vtkRPScene::EndBatchProcess() {
  if (this->BatchDepth == 0) return;
  if (--this->BatchDepth == 0) this->InvokeEvent(EndBatchProcessEvent);
}
