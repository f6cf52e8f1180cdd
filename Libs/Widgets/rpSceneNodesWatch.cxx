#include "rpSceneNodesWatch.h"

#include <vtkCallbackCommand.h>

#include "vtkRPScene.h"

namespace rp {

SceneNodesWatch::SceneNodesWatch(vtkRPScene* scene) : Scene(scene) {
  if (!scene) return;
  this->Callback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->Callback->SetClientData(this);
  this->Callback->SetCallback(&SceneNodesWatch::OnChanged);
  for (unsigned long event : {static_cast<unsigned long>(vtkRPScene::NodeAddedEvent),
                              static_cast<unsigned long>(vtkRPScene::NodeRemovedEvent),
                              static_cast<unsigned long>(vtkRPScene::EndImportEvent),
                              static_cast<unsigned long>(vtkRPScene::EndCloseEvent)})
    this->Tags.push_back(scene->AddObserver(event, this->Callback));
}

SceneNodesWatch::~SceneNodesWatch() {
  if (this->Scene)
    for (unsigned long tag : this->Tags) this->Scene->RemoveObserver(tag);
}

bool SceneNodesWatch::TakeChanged() {
  const bool changed = this->Changed;
  this->Changed = false;
  return changed;
}

void SceneNodesWatch::OnChanged(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<SceneNodesWatch*>(clientData)->Changed = true;
}

}  // namespace rp
