#include "rpViewController.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>

#include "rpView.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"
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

bool HasVoxels(vtkRPScalarVolumeNode* volume) {
  return volume && volume->GetImageData() && volume->GetImageData()->GetNumberOfPoints() > 0;
}

bool IsVisibleModel(vtkRPNode* node) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  return model && model->GetVisibility() && model->GetPolyData() && model->GetPolyData()->GetNumberOfPoints() > 0;
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
  const std::vector<vtkRPSliceNode*> nodes = vtkRPSliceNode::GetOrAddDefaultSliceNodes(scene);
  SliceViewNodes slices;
  for (size_t i = 0; i < 3 && i < nodes.size(); ++i) {
    this->SliceNodes[i] = nodes[i];
    this->SliceLogics[i] = vtkSmartPointer<vtkRPSliceLogic>::New();
    this->SliceLogics[i]->SetSliceNode(scene, nodes[i]);
    slices.Nodes[i] = nodes[i];
    slices.Logics[i] = this->SliceLogics[i];
  }
  this->Layout = vtkRPLayoutNode::GetOrAddLayoutNode(scene);
  for (int i = 0; i < 4; ++i) {
    this->Views[static_cast<size_t>(i)] = std::make_unique<View>(static_cast<ViewKind>(i), scene, this->State, slices);
  }
  this->SceneCallback->SetClientData(this);
  this->SceneCallback->SetCallback(&ViewController::OnSceneEvent);
  for (unsigned long event : {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeAboutToBeRemovedEvent,
                              vtkRPScene::NodeRemovedEvent, vtkRPScene::EndImportEvent}) {
    this->SceneTags.push_back(scene->AddObserver(event, this->SceneCallback));
  }
  // What is already in the scene: layers where the slice nodes have none (a loaded scene keeps
  // its own), and the views framed.
  if (this->AssignDefaultLayers()) {
    this->ResetViews();
  } else {
    this->ResetCameras3D();
  }
}

ViewController::~ViewController() {
  if (this->Scene) {
    for (unsigned long tag : this->SceneTags) this->Scene->RemoveObserver(tag);
  }
  for (auto& view : this->Views) view.reset();
  for (auto& logic : this->SliceLogics) {
    if (logic) logic->SetSliceNode(nullptr, nullptr);
  }
}

vtkRPSliceNode* ViewController::GetSliceNode(ViewKind kind) const {
  return IsSliceView(kind) ? this->SliceNodes[static_cast<size_t>(kind)].GetPointer() : nullptr;
}

vtkRPLayoutNode* ViewController::GetLayoutNode() const { return this->Layout; }

vtkRPSliceLogic* ViewController::GetSliceLogic(ViewKind kind) const {
  return IsSliceView(kind) ? this->SliceLogics[static_cast<size_t>(kind)].GetPointer() : nullptr;
}

void ViewController::OnSceneEvent(vtkObject*, unsigned long event, void* clientData, void* callData) {
  auto* self = static_cast<ViewController*>(clientData);
  auto* object = static_cast<vtkObject*>(callData);
  switch (event) {
    case vtkRPScene::NodeAddedEvent: self->OnNodeAdded(object); break;
    case vtkRPScene::NodeAboutToBeRemovedEvent: self->OnNodeAboutToBeRemoved(object); break;
    case vtkRPScene::NodeRemovedEvent: self->OnNodeRemoved(object); break;
    case vtkRPScene::EndImportEvent: self->OnEndImport(); break;
    default: break;
  }
}

bool ViewController::AssignDefaultLayers() {
  if (!this->Scene) return false;
  std::vector<vtkRPScalarVolumeNode*> volumes;
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPScalarVolumeNode")) {
    auto* volume = vtkRPScalarVolumeNode::SafeDownCast(node);
    if (HasVoxels(volume)) volumes.push_back(volume);
  }
  std::vector<vtkRPNode*> segmentations = this->Scene->GetNodesByClass("vtkRPSegmentationNode");
  bool backgroundGiven = false;
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (!node) continue;
    const int previous = node->StartModify();
    const bool labelGiven = node->GetLabelNodeID().empty() && !segmentations.empty();
    if (labelGiven) node->SetLabelNodeID(segmentations[0]->GetID());
    auto* background = vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(node->GetBackgroundVolumeID()));
    if (!HasVoxels(background)) {
      // The volume the segmentation was drawn on (a DICOM SEG's series), else the first volume.
      auto* label = this->Scene->GetNodeByID(node->GetLabelNodeID());
      auto* drawnOn = vtkRPScalarVolumeNode::SafeDownCast(
          label ? label->GetNodeReference(vtkRPSegmentationNode::ReferenceImageGeometryRole()) : nullptr);
      background = HasVoxels(drawnOn) ? drawnOn : volumes.empty() ? nullptr : volumes[0];
      if (background) node->SetBackgroundVolumeID(background->GetID());
      // Something new to frame: a background, or a segmentation shown alone.
      backgroundGiven = backgroundGiven || background || labelGiven;
    }
    // A second volume (e.g. a registered MR) shows over the CT at once.
    if (node->GetForegroundVolumeID().empty() || !this->Scene->GetNodeByID(node->GetForegroundVolumeID())) {
      for (vtkRPScalarVolumeNode* volume : volumes) {
        if (volume != background) {
          node->SetForegroundVolumeID(volume->GetID());
          break;
        }
      }
    }
    node->EndModify(previous);
  }
  return backgroundGiven;
}

void ViewController::OnNodeAdded(vtkObject* object) {
  if (!this->Scene || this->Scene->IsImporting()) return;  // the import's end handles it
  if (vtkRPScalarVolumeNode::SafeDownCast(object) || vtkRPSegmentationNode::SafeDownCast(object)) {
    if (this->AssignDefaultLayers()) this->ResetViews();
  } else if (!this->Has3DContent && IsVisibleModel(vtkRPNode::SafeDownCast(object))) {
    this->ResetCameras3D();  // the first model: frame it
  }
}

void ViewController::OnEndImport() {
  // A scene that brought its slice nodes keeps its planes; otherwise the slices centre on the
  // new background. The 3D camera frames what was loaded either way.
  if (this->AssignDefaultLayers()) {
    this->ResetViews();
  } else {
    this->ResetCameras3D();
  }
}

void ViewController::OnNodeAboutToBeRemoved(vtkObject* object) {
  auto* node = vtkRPNode::SafeDownCast(object);
  if (!node) return;
  if (node->GetID() == this->State->GetActiveFiducialListID()) this->State->SetActiveFiducialListID("");
}

void ViewController::OnNodeRemoved(vtkObject* object) {
  // The views' own nodes stay in the scene (a module removing one gets it back, reset).
  for (auto& node : this->SliceNodes) {
    if (node && node.GetPointer() == object && this->Scene && !this->Scene->IsClosing()) this->Scene->AddNode(node);
  }
  if (this->Layout && this->Layout.GetPointer() == object && this->Scene) this->Scene->AddNode(this->Layout);
  // A removed background is replaced by what remains (the foreground, if any).
  if (vtkRPScalarVolumeNode::SafeDownCast(object) || vtkRPSegmentationNode::SafeDownCast(object)) {
    for (vtkRPSliceNode* sliceNode : this->SliceNodes) {
      if (sliceNode && sliceNode->GetBackgroundVolumeID().empty() && !sliceNode->GetForegroundVolumeID().empty()) {
        const int previous = sliceNode->StartModify();
        sliceNode->SetBackgroundVolumeID(sliceNode->GetForegroundVolumeID());
        sliceNode->SetForegroundVolumeID("");
        sliceNode->EndModify(previous);
      }
    }
  }
}

void ViewController::SetSlicePointRAS(const double ras[3]) {
  if (!std::isfinite(ras[0]) || !std::isfinite(ras[1]) || !std::isfinite(ras[2])) return;
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->JumpSlice(ras);
  }
}

void ViewController::GetSlicePointRAS(double ras[3]) const {
  // Solve n_i · x = offset_i for the three planes.
  double a[3][3], b[3];
  for (int i = 0; i < 3; ++i) {
    vtkRPSliceNode* node = this->SliceNodes[static_cast<size_t>(i)];
    if (!node) {
      ras[0] = ras[1] = ras[2] = 0;
      return;
    }
    node->GetNormal(a[i]);
    b[i] = node->GetSliceOffset();
  }
  const double det = vtkMath::Determinant3x3(a);
  if (std::fabs(det) < 1e-9) {
    this->SliceNodes[0]->GetOrigin(ras);
    return;
  }
  double inverse[3][3];
  vtkMath::Invert3x3(a, inverse);
  for (int r = 0; r < 3; ++r) ras[r] = inverse[r][0] * b[0] + inverse[r][1] * b[1] + inverse[r][2] * b[2];
}

void ViewController::SetFollowTransformNodeID(const std::string& id) {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->SetAndObserveFollowNodeID(id);
  }
}

std::string ViewController::GetFollowTransformNodeID() const {
  return this->SliceNodes[0] ? this->SliceNodes[0]->GetFollowNodeID() : std::string();
}

void ViewController::SetBackgroundVolumeID(const std::string& id) {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->SetBackgroundVolumeID(id);
  }
}

void ViewController::SetForegroundVolumeID(const std::string& id) {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->SetForegroundVolumeID(id);
  }
}

void ViewController::SetForegroundOpacity(double opacity) {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->SetForegroundOpacity(opacity);
  }
}

void ViewController::SetSlicesVisibleIn3D(bool visible) {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node) node->SetSliceVisible(visible);
  }
}

bool ViewController::GetSlicesVisibleIn3D() const {
  for (vtkRPSliceNode* node : this->SliceNodes) {
    if (node && node->GetSliceVisible()) return true;
  }
  return false;
}

vtkRPScalarVolumeNode* ViewController::GetBackgroundVolume() const {
  if (!this->Scene || !this->SliceNodes[0]) return nullptr;
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->SliceNodes[0]->GetBackgroundVolumeID()));
}

vtkRPScalarVolumeNode* ViewController::GetForegroundVolume() const {
  if (!this->Scene || !this->SliceNodes[0]) return nullptr;
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(this->SliceNodes[0]->GetForegroundVolumeID()));
}

void ViewController::MoveSlice(ViewKind kind, int steps) {
  vtkRPSliceNode* node = this->GetSliceNode(kind);
  if (!node || steps == 0) return;
  node->SetSliceOffset(node->GetSliceOffset() + this->GetView(kind)->GetSliceStep() * steps);
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
  // Models are in layer 0, the slices in layer 1: the hit nearest the camera wins.
  double camera[3];
  view->GetRenderer()->GetActiveCamera()->GetPosition(camera);
  bool hit = false;
  double ras[3], nearest = 0;
  for (vtkRenderer* layer : {view->GetRenderer(), view->GetOverlayRenderer()}) {
    vtkNew<vtkCellPicker> picker;
    picker->SetTolerance(0.0005);
    if (!picker->Pick(x, y, 0, layer)) continue;
    double position[3];
    picker->GetPickPosition(position);
    const double distance = vtkMath::Distance2BetweenPoints(position, camera);
    if (!hit || distance < nearest) {
      std::copy(position, position + 3, ras);
      nearest = distance;
      hit = true;
    }
  }
  return hit && this->PlaceFiducial(ras) != nullptr;
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
  vtkRPSliceNode* sliceNode = this->GetSliceNode(kind);
  if (!sliceNode || !this->Scene) return false;
  View* view = this->GetView(kind);
  double normal[3];
  sliceNode->GetNormal(normal);
  const double offset = sliceNode->GetSliceOffset();
  const double tolerance = 0.5 * view->GetSliceStep() + 1e-6;  // as the fiducial manager draws them
  double best = pixels * pixels;
  bool found = false;
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPFiducialListNode")) {
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    for (int i = 0; i < list->GetNumberOfControlPoints(); ++i) {
      if (!list->GetNthControlPoint(i).Visible) continue;
      double world[3], display[2];
      list->GetNthControlPointPositionWorld(i, world);
      if (std::fabs(vtkMath::Dot(normal, world) - offset) > tolerance) continue;
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
  // The slices through the middle of the background, else of the segmentation shown alone (its
  // labelled voxels).
  vtkRPImageNode* image = this->GetBackgroundVolume();
  if (!HasVoxels(vtkRPScalarVolumeNode::SafeDownCast(image)) && this->Scene && this->SliceNodes[0])
    image = vtkRPSegmentationNode::SafeDownCast(this->Scene->GetNodeByID(this->SliceNodes[0]->GetLabelNodeID()));
  if (image && image->GetImageData() && image->GetImageData()->GetNumberOfPoints() > 0) {
    double bounds[6];
    vtkRPSliceLogic::ComputeShownRASBounds(image, bounds);
    const double center[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
    this->SetSlicePointRAS(center);
  }
  this->ResetCameras();
}

void ViewController::ResetCameras() {
  for (auto& view : this->Views) view->ResetCamera();
  this->Has3DContent = this->HasFramingContent();
}

void ViewController::ResetCameras3D() {
  this->GetView(ViewKind::ThreeD)->ResetCamera();
  this->Has3DContent = this->HasFramingContent();
}

bool ViewController::HasFramingContent() const {
  if (!this->Scene) return false;
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPModelNode")) {
    if (IsVisibleModel(node)) return true;
  }
  return false;
}

}  // namespace rp
