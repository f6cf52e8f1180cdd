#include "vtkRPVolumeSliceDisplayableManager.h"

#include <vtkImageActor.h>
#include <vtkObjectFactory.h>
#include <vtkRenderer.h>

#include "rpSliceReslicer.h"
#include "rpView.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPViewState.h"

vtkStandardNewMacro(vtkRPVolumeSliceDisplayableManager);

vtkRPVolumeSliceDisplayableManager::vtkRPVolumeSliceDisplayableManager() = default;

vtkRPVolumeSliceDisplayableManager::~vtkRPVolumeSliceDisplayableManager() {
  this->Finalize();
}

bool vtkRPVolumeSliceDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPScalarVolumeNode::SafeDownCast(node) != nullptr;
}

void vtkRPVolumeSliceDisplayableManager::AddDisplay(vtkRPNode*) {
  rp::View* view = this->GetView();
  if (this->Reslicers.empty() && view) {
    if (view->IsSlice()) {
      this->Reslicers.push_back(std::make_unique<rp::SliceReslicer>(view->GetKind()));
    } else {
      for (rp::ViewKind kind : {rp::ViewKind::Axial, rp::ViewKind::Sagittal, rp::ViewKind::Coronal}) {
        this->Reslicers.push_back(std::make_unique<rp::SliceReslicer>(kind));
      }
    }
    for (auto& reslicer : this->Reslicers) view->GetRenderer()->AddViewProp(reslicer->GetActor());
  }
}

void vtkRPVolumeSliceDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  this->Refresh(node);
  if (this->GetNumberOfDisplayedNodes() == 0 && this->GetView()) {
    for (auto& reslicer : this->Reslicers) this->GetView()->GetRenderer()->RemoveViewProp(reslicer->GetActor());
    this->Reslicers.clear();
  }
}

void vtkRPVolumeSliceDisplayableManager::UpdateDisplay(vtkRPNode*) { this->Refresh(nullptr); }

void vtkRPVolumeSliceDisplayableManager::OnViewStateModified() {
  this->Refresh(nullptr);
  this->RequestRender();
}

// Re-resolves the layers from the view state (a volume about to leave the scene is skipped).
void vtkRPVolumeSliceDisplayableManager::Refresh(vtkRPNode* leaving) {
  vtkRPScene* scene = this->GetScene();
  vtkRPViewState* state = this->GetViewState();
  if (!scene || !state || this->Reslicers.empty()) return;
  auto resolve = [&](const std::string& id) -> vtkRPScalarVolumeNode* {
    vtkRPNode* node = scene->GetNodeByID(id);
    if (!node || node == leaving || !this->IsDisplayed(node)) return nullptr;
    return vtkRPScalarVolumeNode::SafeDownCast(node);
  };
  vtkRPScalarVolumeNode* background = resolve(state->GetBackgroundVolumeID());
  vtkRPScalarVolumeNode* foreground = resolve(state->GetForegroundVolumeID());
  const bool visible = this->GetView()->IsSlice() || state->GetSlicesVisibleIn3D();
  for (auto& reslicer : this->Reslicers) {
    reslicer->SetVolumes(visible ? background : nullptr, visible ? foreground : nullptr, state->GetForegroundOpacity());
    reslicer->SetSlicePoint(state->GetSlicePointRAS());
    reslicer->Update();
  }
}
