#include "rpViewController.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <vtkCallbackCommand.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>

#include "rpView.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTransformableNode.h"
#include "vtkRPViewState.h"

namespace rp {

namespace {

// Percentiles of a volume's voxel values from a sorted sample (at most ~200k voxels read).
bool Percentiles(vtkRPScalarVolumeNode* volume, double low, double high, double& lowValue, double& highValue) {
  vtkImageData* image = volume ? volume->GetImageData() : nullptr;
  vtkDataArray* scalars = image && image->GetPointData() ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars || scalars->GetNumberOfTuples() == 0) return false;
  const vtkIdType count = scalars->GetNumberOfTuples();
  const vtkIdType stride = std::max<vtkIdType>(1, count / 200000);
  std::vector<double> sample;
  sample.reserve(static_cast<size_t>(count / stride + 1));
  for (vtkIdType i = 0; i < count; i += stride) sample.push_back(scalars->GetComponent(i, 0));
  std::sort(sample.begin(), sample.end());
  lowValue = sample[static_cast<size_t>(low * double(sample.size() - 1))];
  highValue = sample[static_cast<size_t>(high * double(sample.size() - 1))];
  return true;
}

}  // namespace

bool GetWindowLevelPreset(WindowLevelPreset preset, vtkRPScalarVolumeNode* volume, double& window, double& level) {
  switch (preset) {
    case WindowLevelPreset::CTBone:  // Slicer's CT-Bone
      window = 1000;
      level = 400;
      return true;
    case WindowLevelPreset::CTSoftTissue:  // Slicer's CT-Abdomen-like soft tissue window
      window = 400;
      level = 40;
      return true;
    case WindowLevelPreset::MR: {
      double lo = 0, hi = 0;
      if (!Percentiles(volume, 0.01, 0.99, lo, hi)) return false;
      window = std::max(1e-3, hi - lo);
      level = 0.5 * (hi + lo);
      return true;
    }
  }
  return false;
}

ViewController::ViewController(vtkRPScene* scene) : Scene(scene) {
  for (int i = 0; i < 4; ++i) {
    this->Views[static_cast<size_t>(i)] = std::make_unique<View>(static_cast<ViewKind>(i), scene, this->State);
  }
  this->SceneCallback->SetClientData(this);
  this->SceneCallback->SetCallback(&ViewController::OnSceneEvent);
  this->SceneTags[0] = scene->AddObserver(vtkRPScene::NodeAddedEvent, this->SceneCallback);
  this->SceneTags[1] = scene->AddObserver(vtkRPScene::NodeAboutToBeRemovedEvent, this->SceneCallback);
  this->FollowCallback->SetClientData(this);
  this->FollowCallback->SetCallback(&ViewController::OnFollowedModified);
  for (vtkRPNode* node : scene->GetNodes()) this->OnNodeAdded(node);
}

ViewController::~ViewController() {
  if (this->Followed) {
    this->Followed->RemoveObserver(this->FollowTags[0]);
    this->Followed->RemoveObserver(this->FollowTags[1]);
  }
  if (this->Scene) {
    this->Scene->RemoveObserver(this->SceneTags[0]);
    this->Scene->RemoveObserver(this->SceneTags[1]);
  }
  for (auto& view : this->Views) view.reset();
}

void ViewController::OnSceneEvent(vtkObject*, unsigned long event, void* clientData, void* callData) {
  auto* self = static_cast<ViewController*>(clientData);
  if (event == vtkRPScene::NodeAddedEvent) self->OnNodeAdded(static_cast<vtkObject*>(callData));
  if (event == vtkRPScene::NodeAboutToBeRemovedEvent) self->OnNodeAboutToBeRemoved(static_cast<vtkObject*>(callData));
}

// The first volume becomes the background (and the slices centre on it); a second one the
// foreground, so a registered MR shows over the CT at once.
void ViewController::OnNodeAdded(vtkObject* object) {
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(object);
  if (!volume) return;
  if (!this->GetBackgroundVolume()) {
    this->State->SetBackgroundVolumeID(volume->GetID());
    this->ResetViews();
  } else if (!this->GetForegroundVolume()) {
    this->State->SetForegroundVolumeID(volume->GetID());
  }
}

void ViewController::OnNodeAboutToBeRemoved(vtkObject* object) {
  auto* node = vtkRPNode::SafeDownCast(object);
  if (!node) return;
  if (node->GetID() == this->FollowID) this->SetFollowTransformNodeID("");
  if (node->GetID() == this->State->GetActiveFiducialListID()) this->State->SetActiveFiducialListID("");
  if (node->GetID() == this->State->GetBackgroundVolumeID()) {
    this->State->SetBackgroundVolumeID(this->State->GetForegroundVolumeID());
    this->State->SetForegroundVolumeID("");
  } else if (node->GetID() == this->State->GetForegroundVolumeID()) {
    this->State->SetForegroundVolumeID("");
  }
}

void ViewController::SetSlicePointRAS(const double ras[3]) {
  if (!std::isfinite(ras[0]) || !std::isfinite(ras[1]) || !std::isfinite(ras[2])) return;
  this->State->SetSlicePointRAS(ras[0], ras[1], ras[2]);
}

void ViewController::GetSlicePointRAS(double ras[3]) const { this->State->GetSlicePointRAS(ras); }

void ViewController::SetFollowTransformNodeID(const std::string& id) {
  if (this->Followed) {
    this->Followed->RemoveObserver(this->FollowTags[0]);
    this->Followed->RemoveObserver(this->FollowTags[1]);
    this->Followed = nullptr;
  }
  this->FollowID.clear();
  if (!this->Scene) return;
  auto* node = vtkRPTransformableNode::SafeDownCast(this->Scene->GetNodeByID(id));
  if (!node) return;
  this->FollowID = id;
  this->Followed = node;
  this->FollowTags[0] = node->AddObserver(vtkCommand::ModifiedEvent, this->FollowCallback);
  this->FollowTags[1] = node->AddObserver(vtkRPNode::TransformModifiedEvent, this->FollowCallback);
  this->UpdateFromFollowed();
}

void ViewController::OnFollowedModified(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<ViewController*>(clientData)->UpdateFromFollowed();
}

void ViewController::UpdateFromFollowed() {
  auto* node = vtkRPTransformableNode::SafeDownCast(this->Followed);
  if (!node) return;
  vtkNew<vtkMatrix4x4> toWorld;
  node->GetMatrixTransformToWorld(toWorld);
  const double tip[3] = {toWorld->GetElement(0, 3), toWorld->GetElement(1, 3), toWorld->GetElement(2, 3)};
  this->SetSlicePointRAS(tip);
}

void ViewController::MoveSlice(ViewKind kind, int steps) {
  if (!IsSliceView(kind) || steps == 0) return;
  const SliceAxes axes = GetSliceAxes(kind);
  const double step = this->GetView(kind)->GetSliceStep() * steps;
  double p[3];
  this->State->GetSlicePointRAS(p);
  for (int i = 0; i < 3; ++i) p[i] += step * axes.Normal[i];
  this->SetSlicePointRAS(p);
}

bool ViewController::ClickInSliceView(ViewKind kind, double x, double y) {
  if (!IsSliceView(kind)) return false;
  double ras[3];
  if (!this->GetView(kind)->DisplayToRAS(x, y, ras)) return false;
  if (this->State->GetInteractionMode() == vtkRPViewState::ModePlaceFiducial) {
    this->PlaceFiducial(ras);
  } else {
    this->SetSlicePointRAS(ras);
  }
  return true;
}

bool ViewController::ClickIn3DView(double x, double y) {
  if (this->State->GetInteractionMode() != vtkRPViewState::ModePlaceFiducial) return false;
  View* view = this->GetView(ViewKind::ThreeD);
  vtkNew<vtkCellPicker> picker;
  picker->SetTolerance(0.0005);
  if (!picker->Pick(x, y, 0, view->GetRenderer())) return false;
  double ras[3];
  picker->GetPickPosition(ras);
  return this->PlaceFiducial(ras) != nullptr;
}

vtkRPFiducialListNode* ViewController::PlaceFiducial(const double ras[3]) {
  if (!this->Scene) return nullptr;
  auto* list = vtkRPFiducialListNode::SafeDownCast(this->Scene->GetNodeByID(this->State->GetActiveFiducialListID()));
  if (!list) {
    vtkNew<vtkRPFiducialListNode> created;
    created->SetName("F");
    this->Scene->AddNode(created);
    list = created;
    this->State->SetActiveFiducialListID(created->GetID());
  }
  // The point is given in world RAS; the list stores it in its own frame.
  vtkNew<vtkMatrix4x4> toWorld, fromWorld;
  list->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Invert(toWorld, fromWorld);
  double in[4] = {ras[0], ras[1], ras[2], 1.0}, local[4];
  fromWorld->MultiplyPoint(in, local);
  list->AddControlPoint(local);
  return list;
}

bool ViewController::FindFiducialAt(ViewKind kind, double x, double y, double pixels, std::string& listID,
                                    int& index) const {
  if (!IsSliceView(kind) || !this->Scene) return false;
  View* view = this->GetView(kind);
  const SliceAxes axes = GetSliceAxes(kind);
  const double* slicePoint = this->State->GetSlicePointRAS();
  const double tolerance = 0.5 * view->GetSliceStep() + 1e-6;  // as the fiducial manager draws them
  double best = pixels * pixels;
  bool found = false;
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPFiducialListNode")) {
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    for (int i = 0; i < list->GetNumberOfControlPoints(); ++i) {
      if (!list->GetNthControlPoint(i).Visible) continue;
      double world[3], display[2];
      list->GetNthControlPointPositionWorld(i, world);
      if (std::fabs(vtkMath::Dot(axes.Normal, world) - vtkMath::Dot(axes.Normal, slicePoint)) > tolerance) continue;
      view->RASToDisplay(world, display);
      const double d2 = (display[0] - x) * (display[0] - x) + (display[1] - y) * (display[1] - y);
      if (d2 <= best) {
        best = d2;
        listID = list->GetID();
        index = i;
        found = true;
      }
    }
  }
  return found;
}

bool ViewController::MoveFiducial(const std::string& listID, int index, const double ras[3]) {
  auto* list = this->Scene ? vtkRPFiducialListNode::SafeDownCast(this->Scene->GetNodeByID(listID)) : nullptr;
  if (!list || index < 0 || index >= list->GetNumberOfControlPoints()) return false;
  vtkNew<vtkMatrix4x4> toWorld, fromWorld;
  list->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Invert(toWorld, fromWorld);
  double in[4] = {ras[0], ras[1], ras[2], 1.0}, local[4];
  fromWorld->MultiplyPoint(in, local);
  return list->SetNthControlPointPosition(index, local);
}

vtkRPScalarVolumeNode* ViewController::GetBackgroundVolume() const {
  if (!this->Scene) return nullptr;
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->State->GetBackgroundVolumeID()));
}

vtkRPScalarVolumeNode* ViewController::GetForegroundVolume() const {
  if (!this->Scene) return nullptr;
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->State->GetForegroundVolumeID()));
}

void ViewController::AdjustWindowLevel(double dx, double dy) {
  vtkRPScalarVolumeNode* volume = this->GetBackgroundVolume();
  if (!volume || !volume->GetImageData()) return;
  double range[2];
  volume->GetImageData()->GetScalarRange(range);
  const double perPixel = std::max(1e-3, (range[1] - range[0]) / 500.0);
  const double window = std::max(1e-3, volume->GetWindow() + dx * perPixel);
  const double level = volume->GetLevel() + dy * perPixel;
  volume->SetWindowLevel(window, level);
}

bool ViewController::ApplyWindowLevelPreset(WindowLevelPreset preset) {
  vtkRPScalarVolumeNode* volume = this->GetBackgroundVolume();
  if (!volume) return false;
  double window = 0, level = 0;
  if (!GetWindowLevelPreset(preset, volume, window, level)) return false;
  volume->SetWindowLevel(window, level);
  return true;
}

void ViewController::ResetViews() {
  if (vtkRPScalarVolumeNode* volume = this->GetBackgroundVolume()) {
    if (volume->GetImageData()) {
      double bounds[6];
      volume->GetRASBounds(bounds);
      const double center[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
      this->SetSlicePointRAS(center);
    }
  }
  this->ResetCameras();
}

void ViewController::ResetCameras() {
  for (auto& view : this->Views) view->ResetCamera();
}

}  // namespace rp
