#include "rpHapticSceneBridge.h"

#include <cmath>
#include <cstdio>

#include <vtkCellArray.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "rpPolyDataTriangleMesh.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"

namespace rp {

std::vector<HapticMeshInput> CollectHapticMeshes(vtkRPScene* scene, std::vector<std::string>& warnings) {
  std::vector<HapticMeshInput> meshes;
  if (scene == nullptr) return meshes;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (model == nullptr || !model->GetHaptic()) continue;
    vtkNew<vtkMatrix4x4> toWorld;
    model->GetMatrixTransformToWorld(toWorld);
    HapticMeshInput input;
    input.Name = model->GetName();
    input.TissueClass = model->GetTissueClass();
    std::string error;
    if (!PolyDataToTriangleMesh(model->GetPolyData(), toWorld, input.Mesh, error)) {
      warnings.push_back("haptic model '" + input.Name + "' skipped: " + error);
      continue;
    }
    meshes.push_back(std::move(input));
  }
  return meshes;
}

unsigned long HapticMeshesSignature(vtkRPScene* scene) {
  unsigned long signature = 0;
  if (scene == nullptr) return signature;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (model == nullptr || !model->GetHaptic()) continue;
    signature = signature * 31 + model->GetMTime();
    if (model->GetPolyData()) signature = signature * 31 + model->GetPolyData()->GetMTime();
    for (vtkRPLinearTransformNode* t = model->GetParentTransformNode(); t; t = t->GetParentTransformNode())
      signature = signature * 31 + t->GetMTime();
  }
  return signature;
}

bool ReadDeviceToScene(vtkRPScene* scene, DeviceToScene& transform) {
  transform = DeviceToScene{};
  if (scene == nullptr) return false;
  auto* node = vtkRPLinearTransformNode::SafeDownCast(scene->GetFirstNodeByName(HapticDeviceToRASName));
  if (node == nullptr) return false;
  vtkNew<vtkMatrix4x4> m;
  node->GetMatrixTransformToWorld(m);
  // A uniform scale (workspace scaling) in the matrix: the column length.
  double scale = 0;
  for (int r = 0; r < 3; ++r) scale += m->GetElement(r, 0) * m->GetElement(r, 0);
  scale = std::sqrt(scale);
  if (!(scale > 0)) scale = 1;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) transform.DeviceToRAS.R[3 * r + c] = m->GetElement(r, c) / scale;
    transform.DeviceToRAS.T[r] = m->GetElement(r, 3);
  }
  transform.Scale = scale;
  return true;
}

Pose PoseFromMatrix(const vtkMatrix4x4* matrix) {
  Pose pose;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.R[3 * r + c] = matrix->GetElement(r, c);
    pose.T[r] = matrix->GetElement(r, 3);
  }
  return pose;
}

bool ReadToolPose(vtkRPScene* scene, const std::string& nodeID, Pose& stylusToRAS) {
  auto* node = scene ? vtkRPTransformableNode::SafeDownCast(scene->GetNodeByID(nodeID)) : nullptr;
  if (node == nullptr) return false;
  vtkNew<vtkMatrix4x4> toWorld;
  node->GetMatrixTransformToWorld(toWorld);
  stylusToRAS = PoseFromMatrix(toWorld);
  return true;
}

namespace {
vtkRPTrackedToolNode* ToolNode(vtkRPScene* scene, const char* name) {
  auto* node = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(name));
  if (node) return node;
  vtkNew<vtkRPTrackedToolNode> created;
  created->SetName(name);
  scene->AddNode(created);
  return created;
}
void SetPose(vtkRPTrackedToolNode* node, const Pose& rotation, const Vec3& position) {
  double e[16] = {rotation.R[0], rotation.R[1], rotation.R[2], position.x, rotation.R[3], rotation.R[4],
                  rotation.R[5], position.y, rotation.R[6], rotation.R[7], rotation.R[8], position.z,
                  0, 0, 0, 1};
  node->SetMatrixTransformToParent(e);
}
}  // namespace

void UpdateToolNodes(vtkRPScene* scene, const HapticState& state, const std::vector<std::string>& labelNames) {
  if (scene == nullptr) return;
  const int status = state.DeviceError ? vtkRPTrackedToolNode::StatusMissing : vtkRPTrackedToolNode::StatusOK;
  vtkRPTrackedToolNode* hip = ToolNode(scene, HapticInterfacePointName);
  int wasModifying = hip->StartModify();
  SetPose(hip, state.Stylus, state.Hip);
  hip->SetTimestamp(state.Time);
  hip->SetStatus(status);
  hip->EndModify(wasModifying);

  vtkRPTrackedToolNode* proxy = ToolNode(scene, HapticProxyName);
  wasModifying = proxy->StartModify();
  SetPose(proxy, state.Stylus, state.Proxy);
  proxy->SetTimestamp(state.Time);
  proxy->SetStatus(status);
  char text[96];
  std::snprintf(text, sizeof(text), "%.4f,%.4f,%.4f", state.Force.x, state.Force.y, state.Force.z);
  proxy->SetAttribute("Force", text);
  proxy->SetAttribute("Contact", state.Contacts > 0 ? "1" : "0");
  proxy->SetAttribute("Tissue", (state.Label >= 0 && static_cast<size_t>(state.Label) < labelNames.size())
                                    ? labelNames[static_cast<size_t>(state.Label)]
                                    : std::string());
  proxy->EndModify(wasModifying);
}

}  // namespace rp
