#include "vtkRPDisplayableManager.h"

#include <vtkCallbackCommand.h>
#include <vtkOpenGLPolyDataMapper.h>
#include <vtkOpenGLVertexBufferObject.h>

#include "rpView.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"
#include "vtkRPViewState.h"

vtkRPDisplayableManager::vtkRPDisplayableManager() {
  this->SceneCallback = vtkCallbackCommand::New();
  this->SceneCallback->SetClientData(this);
  this->SceneCallback->SetCallback(&vtkRPDisplayableManager::OnSceneEvent);
  this->NodeCallback = vtkCallbackCommand::New();
  this->NodeCallback->SetClientData(this);
  this->NodeCallback->SetCallback(&vtkRPDisplayableManager::OnNodeEvent);
  this->StateCallback = vtkCallbackCommand::New();
  this->StateCallback->SetClientData(this);
  this->StateCallback->SetCallback(&vtkRPDisplayableManager::OnStateEvent);
}

vtkRPDisplayableManager::~vtkRPDisplayableManager() {
  this->Finalize();
  this->SceneCallback->Delete();
  this->NodeCallback->Delete();
  this->StateCallback->Delete();
}

void vtkRPDisplayableManager::SkipVertexShift(vtkMapper* mapper) {
  if (auto* gl = vtkOpenGLPolyDataMapper::SafeDownCast(mapper)) {
    gl->SetVBOShiftScaleMethod(vtkOpenGLVertexBufferObject::DISABLE_SHIFT_SCALE);
  }
}

vtkRPScene* vtkRPDisplayableManager::GetScene() const { return this->Scene; }
vtkRPViewState* vtkRPDisplayableManager::GetViewState() const { return this->State; }
vtkRPSliceNode* vtkRPDisplayableManager::GetSliceNode() const { return this->SliceNode; }

void vtkRPDisplayableManager::Initialize(rp::View* view) {
  this->Finalize();
  this->View = view;
  this->Scene = view->GetScene();
  this->State = view->GetViewState();
  for (unsigned long event : {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeAboutToBeRemovedEvent}) {
    this->SceneTags.push_back(this->Scene->AddObserver(event, this->SceneCallback));
  }
  this->StateTag = this->State->AddObserver(vtkCommand::ModifiedEvent, this->StateCallback);
  this->SliceNode = view->GetSliceNode();
  if (this->SliceNode) this->SliceNodeTag = this->SliceNode->AddObserver(vtkCommand::ModifiedEvent, this->StateCallback);
  this->OnInitialize();
  for (vtkRPNode* node : this->Scene->GetNodes()) this->StartDisplaying(node);
  this->OnViewStateModified();
}

void vtkRPDisplayableManager::Finalize() {
  if (this->View) this->OnFinalize();
  while (!this->Observed.empty()) {
    auto it = this->Observed.begin();
    if (it->second.Node) {
      this->StopDisplaying(it->first);
    } else {
      this->Observed.erase(it);  // the node is gone (scene deleted first): nothing to unobserve
    }
  }
  if (this->Scene) {
    for (unsigned long tag : this->SceneTags) this->Scene->RemoveObserver(tag);
  }
  this->SceneTags.clear();
  if (this->State && this->StateTag) this->State->RemoveObserver(this->StateTag);
  this->StateTag = 0;
  if (this->SliceNode && this->SliceNodeTag) this->SliceNode->RemoveObserver(this->SliceNodeTag);
  this->SliceNodeTag = 0;
  this->SliceNode = nullptr;
  this->View = nullptr;
}

void vtkRPDisplayableManager::StartDisplaying(vtkRPNode* node) {
  if (!node || this->Observed.count(node) || !this->CanDisplay(node)) return;
  ObservedNode& entry = this->Observed[node];
  entry.Node = node;
  std::vector<unsigned long> events = {vtkCommand::ModifiedEvent, vtkRPNode::TransformModifiedEvent};
  for (unsigned long event : this->ExtraNodeEvents()) events.push_back(event);
  for (unsigned long event : events) entry.Tags.push_back(node->AddObserver(event, this->NodeCallback));
  this->AddDisplay(node);
  this->UpdateDisplay(node);
  this->RequestRender();
}

void vtkRPDisplayableManager::StopDisplaying(vtkRPNode* node) {
  auto it = this->Observed.find(node);
  if (it == this->Observed.end()) return;
  for (unsigned long tag : it->second.Tags) node->RemoveObserver(tag);
  this->Observed.erase(it);
  this->RemoveDisplay(node);
  this->RequestRender();
}

std::vector<vtkRPNode*> vtkRPDisplayableManager::GetDisplayedNodes() const {
  std::vector<vtkRPNode*> nodes;
  for (const auto& entry : this->Observed) {
    if (entry.second.Node) nodes.push_back(entry.first);
  }
  return nodes;
}

void vtkRPDisplayableManager::RequestRender() {
  if (this->View) this->View->RequestRender();
}

void vtkRPDisplayableManager::OnSceneEvent(vtkObject*, unsigned long event, void* clientData, void* callData) {
  auto* self = static_cast<vtkRPDisplayableManager*>(clientData);
  auto* node = static_cast<vtkRPNode*>(callData);
  if (event == vtkRPScene::NodeAddedEvent) {
    self->StartDisplaying(node);
  } else if (event == vtkRPScene::NodeAboutToBeRemovedEvent) {
    self->StopDisplaying(node);
  }
}

void vtkRPDisplayableManager::OnNodeEvent(vtkObject* caller, unsigned long, void* clientData, void*) {
  auto* self = static_cast<vtkRPDisplayableManager*>(clientData);
  auto* node = static_cast<vtkRPNode*>(caller);
  if (!self->Observed.count(node)) return;
  self->UpdateDisplay(node);
  self->RequestRender();
}

void vtkRPDisplayableManager::OnStateEvent(vtkObject*, unsigned long, void* clientData, void*) {
  auto* self = static_cast<vtkRPDisplayableManager*>(clientData);
  self->OnViewStateModified();
}

void vtkRPDisplayableManager::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DisplayedNodes: " << this->Observed.size() << "\n";
}
