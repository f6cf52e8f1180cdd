#include "vtkRPSliceNode.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <vtkCallbackCommand.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>

#include "vtkRPScene.h"
#include "vtkRPTransformableNode.h"

vtkStandardNewMacro(vtkRPSliceNode);

namespace {

struct Preset {
  const char* Orientation;
  const char* LayoutName;
  double Matrix[3][3];  // row-major SliceToRAS rotation: columns right, up, normal
};

// Slicer's vtkMRMLSliceNode::InitializeAxialMatrix / InitializeSagittalMatrix /
// InitializeCoronalMatrix, element for element.
const Preset Presets[] = {
    {"Axial", "Red", {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
    {"Sagittal", "Yellow", {{0, 0, 1}, {-1, 0, 0}, {0, 1, 0}}},
    {"Coronal", "Green", {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}}},
};

bool Finite3(const double v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

vtkRPSliceNode::vtkRPSliceNode() {
  this->FollowCallback = vtkCallbackCommand::New();
  this->FollowCallback->SetClientData(this);
  this->FollowCallback->SetCallback(&vtkRPSliceNode::OnFollowedEvent);
  double m[3][3];
  GetOrientationMatrix(this->Orientation, m);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) this->SliceToRAS->SetElement(r, c, m[r][c]);
}

vtkRPSliceNode::~vtkRPSliceNode() {
  if (this->Followed) {
    for (unsigned long tag : this->FollowTags) this->Followed->RemoveObserver(tag);
  }
  this->FollowCallback->Delete();
}

vtkRPNode* vtkRPSliceNode::CreateNodeInstance() { return vtkRPSliceNode::New(); }

void vtkRPSliceNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LayoutName: " << this->GetLayoutName() << "\n"
     << indent << "Orientation: " << this->Orientation << "\n"
     << indent << "FieldOfView: " << this->FieldOfView[0] << " " << this->FieldOfView[1] << "\n"
     << indent << "SliceToRAS:\n";
  this->SliceToRAS->PrintSelf(os, indent.GetNextIndent());
}

// ---------------------------------------------------------------- the standard frames

bool vtkRPSliceNode::GetOrientationMatrix(const std::string& orientation, double matrix[3][3]) {
  for (const Preset& preset : Presets) {
    if (orientation != preset.Orientation) continue;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) matrix[r][c] = preset.Matrix[r][c];
    return true;
  }
  return false;
}

bool vtkRPSliceNode::ComputeSliceToRAS(const std::string& orientation, const double pointRAS[3], vtkMatrix4x4* sliceToRAS) {
  double m[3][3];
  if (!sliceToRAS || !GetOrientationMatrix(orientation, m)) return false;
  sliceToRAS->Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) sliceToRAS->SetElement(r, c, m[r][c]);
    sliceToRAS->SetElement(r, 3, pointRAS[r]);
  }
  return true;
}

void vtkRPSliceNode::ComputeSliceToRASForTool(const vtkMatrix4x4* toolTipToRAS, vtkMatrix4x4* sliceToRAS) {
  sliceToRAS->Identity();
  double x[3], y[3], n[3];
  for (int r = 0; r < 3; ++r) {
    x[r] = toolTipToRAS->GetElement(r, 0);
    y[r] = toolTipToRAS->GetElement(r, 2);
  }
  vtkMath::Cross(x, y, n);  // = −(tool y) for a rigid tool frame
  for (int r = 0; r < 3; ++r) {
    sliceToRAS->SetElement(r, 0, x[r]);
    sliceToRAS->SetElement(r, 1, y[r]);
    sliceToRAS->SetElement(r, 2, n[r]);
    sliceToRAS->SetElement(r, 3, toolTipToRAS->GetElement(r, 3));
  }
}

std::string vtkRPSliceNode::GetDefaultOrientationForLayoutName(const std::string& layoutName) {
  for (const Preset& preset : Presets) {
    if (layoutName == preset.LayoutName) return preset.Orientation;
  }
  return {};
}

// ---------------------------------------------------------------- the plane

void vtkRPSliceNode::SetLayoutName(const std::string& name) {
  if (name == this->GetSingletonTag()) return;
  this->SetSingletonTag(name);
  this->Modified();
}

bool vtkRPSliceNode::SetOrientation(const std::string& orientation) {
  double origin[3];
  this->GetOrigin(origin);
  vtkNew<vtkMatrix4x4> sliceToRAS;
  if (!ComputeSliceToRAS(orientation, origin, sliceToRAS)) return false;
  return this->SetSliceToRAS(sliceToRAS);
}

void vtkRPSliceNode::GetSliceToRAS(vtkMatrix4x4* sliceToRAS) const { sliceToRAS->DeepCopy(this->SliceToRAS); }

bool vtkRPSliceNode::SetSliceToRAS(const vtkMatrix4x4* sliceToRAS) {
  if (!sliceToRAS) return false;
  double x[3], y[3], n[3], t[3];
  for (int r = 0; r < 3; ++r) {
    x[r] = sliceToRAS->GetElement(r, 0);
    y[r] = sliceToRAS->GetElement(r, 1);
    n[r] = sliceToRAS->GetElement(r, 2);
    t[r] = sliceToRAS->GetElement(r, 3);
  }
  if (!Finite3(x) || !Finite3(y) || !Finite3(n) || !Finite3(t)) return false;
  // Orthonormal columns (Gram–Schmidt on right and up; the normal keeps its side).
  if (vtkMath::Normalize(x) < 1e-9) return false;
  const double xy = vtkMath::Dot(x, y);
  for (int r = 0; r < 3; ++r) y[r] -= xy * x[r];
  if (vtkMath::Normalize(y) < 1e-9) return false;
  double cross[3];
  vtkMath::Cross(x, y, cross);
  const double side = vtkMath::Dot(cross, n);
  if (std::fabs(side) < 1e-9) return false;  // the normal lies in the plane
  for (int r = 0; r < 3; ++r) n[r] = side > 0 ? cross[r] : -cross[r];

  std::string orientation = ReformatOrientationName();
  for (const Preset& preset : Presets) {
    double difference = 0;
    for (int r = 0; r < 3; ++r) {
      difference = std::max({difference, std::fabs(x[r] - preset.Matrix[r][0]), std::fabs(y[r] - preset.Matrix[r][1]),
                             std::fabs(n[r] - preset.Matrix[r][2])});
    }
    if (difference < 1e-6) orientation = preset.Orientation;
  }
  bool changed = orientation != this->Orientation;
  for (int r = 0; r < 3; ++r) {
    const double column[4] = {x[r], y[r], n[r], t[r]};
    for (int c = 0; c < 4; ++c) {
      if (this->SliceToRAS->GetElement(r, c) != column[c]) {
        this->SliceToRAS->SetElement(r, c, column[c]);
        changed = true;
      }
    }
  }
  this->Orientation = orientation;
  if (changed) {
    this->SliceToRAS->Modified();
    this->Modified();
  }
  return true;
}

void vtkRPSliceNode::GetNormal(double normal[3]) const {
  for (int r = 0; r < 3; ++r) normal[r] = this->SliceToRAS->GetElement(r, 2);
}

void vtkRPSliceNode::GetOrigin(double originRAS[3]) const {
  for (int r = 0; r < 3; ++r) originRAS[r] = this->SliceToRAS->GetElement(r, 3);
}

double vtkRPSliceNode::GetSliceOffset() const {
  double normal[3], origin[3];
  this->GetNormal(normal);
  this->GetOrigin(origin);
  return vtkMath::Dot(normal, origin);
}

void vtkRPSliceNode::SetSliceOffset(double offset) {
  if (!std::isfinite(offset)) return;
  double normal[3], origin[3];
  this->GetNormal(normal);
  this->GetOrigin(origin);
  const double shift = offset - vtkMath::Dot(normal, origin);
  if (shift == 0.0) return;
  for (int r = 0; r < 3; ++r) this->SliceToRAS->SetElement(r, 3, origin[r] + shift * normal[r]);
  this->SliceToRAS->Modified();
  this->Modified();
}

void vtkRPSliceNode::JumpSlice(const double ras[3]) {
  if (!ras || !Finite3(ras)) return;
  double normal[3];
  this->GetNormal(normal);
  this->SetSliceOffset(vtkMath::Dot(normal, ras));
}

// ---------------------------------------------------------------- view and layers

void vtkRPSliceNode::SetFieldOfView(double width, double height) {
  if (!(width > 0) || !(height > 0) || !std::isfinite(width) || !std::isfinite(height)) return;
  if (width == this->FieldOfView[0] && height == this->FieldOfView[1]) return;
  this->FieldOfView[0] = width;
  this->FieldOfView[1] = height;
  this->Modified();
}

void vtkRPSliceNode::SetXYOrigin(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  if (x == this->XYOrigin[0] && y == this->XYOrigin[1]) return;
  this->XYOrigin[0] = x;
  this->XYOrigin[1] = y;
  this->Modified();
}

void vtkRPSliceNode::SetSliceVisible(bool visible) {
  if (visible == this->SliceVisible) return;
  this->SliceVisible = visible;
  this->Modified();
}

void vtkRPSliceNode::SetForegroundOpacity(double opacity) {
  opacity = std::clamp(std::isfinite(opacity) ? opacity : 0.0, 0.0, 1.0);
  if (opacity == this->ForegroundOpacity) return;
  this->ForegroundOpacity = opacity;
  this->Modified();
}

void vtkRPSliceNode::SetLabelOpacity(double opacity) {
  opacity = std::clamp(std::isfinite(opacity) ? opacity : 0.0, 0.0, 1.0);
  if (opacity == this->LabelOpacity) return;
  this->LabelOpacity = opacity;
  this->Modified();
}

// ---------------------------------------------------------------- following a tool

bool vtkRPSliceNode::SetAndObserveFollowNodeID(const std::string& id) {
  if (!id.empty() && this->GetScene() && !vtkRPTransformableNode::SafeDownCast(this->GetScene()->GetNodeByID(id))) {
    vtkErrorMacro("SetAndObserveFollowNodeID: '" << id << "' is not a transformable node in the scene");
    return false;
  }
  this->SetNodeReferenceID(FollowRole(), id);
  return true;
}

void vtkRPSliceNode::OnNodeReferenceChanged(const std::string& role) {
  this->Superclass::OnNodeReferenceChanged(role);
  if (role == FollowRole()) this->ObserveFollowedNode();
}

void vtkRPSliceNode::UpdateReferences() {
  this->Superclass::UpdateReferences();
  this->ObserveFollowedNode();
}

void vtkRPSliceNode::ObserveFollowedNode() {
  vtkRPNode* target = vtkRPTransformableNode::SafeDownCast(this->GetNodeReference(FollowRole()));
  if (target != this->Followed) {
    if (this->Followed) {
      for (unsigned long tag : this->FollowTags) this->Followed->RemoveObserver(tag);
    }
    this->Followed = target;
    if (target) {
      this->FollowTags[0] = target->AddObserver(vtkRPNode::TransformModifiedEvent, this->FollowCallback);
      this->FollowTags[1] = target->AddObserver(vtkCommand::ModifiedEvent, this->FollowCallback);
      this->FollowTags[2] = target->AddObserver(vtkCommand::DeleteEvent, this->FollowCallback);
    }
  }
  this->UpdateFromFollowedNode();
}

void vtkRPSliceNode::OnFollowedEvent(vtkObject* caller, unsigned long event, void* clientData, void*) {
  auto* self = static_cast<vtkRPSliceNode*>(clientData);
  if (event == vtkCommand::DeleteEvent) {
    if (caller == self->Followed) self->Followed = nullptr;
    return;
  }
  self->UpdateFromFollowedNode();
}

void vtkRPSliceNode::UpdateFromFollowedNode() {
  auto* node = vtkRPTransformableNode::SafeDownCast(this->Followed);
  if (!node) return;
  vtkNew<vtkMatrix4x4> toWorld;
  node->GetMatrixTransformToWorld(toWorld);
  const double tip[3] = {toWorld->GetElement(0, 3), toWorld->GetElement(1, 3), toWorld->GetElement(2, 3)};
  this->JumpSlice(tip);
}

// ---------------------------------------------------------------- the scene's slice nodes

std::vector<vtkRPSliceNode*> vtkRPSliceNode::GetSliceNodes(vtkRPScene* scene) {
  std::vector<vtkRPSliceNode*> nodes;
  if (!scene) return nodes;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSliceNode")) nodes.push_back(static_cast<vtkRPSliceNode*>(node));
  return nodes;
}

vtkRPSliceNode* vtkRPSliceNode::GetSliceNode(vtkRPScene* scene, const std::string& layoutName) {
  return scene ? vtkRPSliceNode::SafeDownCast(scene->GetSingletonNode(layoutName, "vtkRPSliceNode")) : nullptr;
}

std::vector<vtkRPSliceNode*> vtkRPSliceNode::GetOrAddDefaultSliceNodes(vtkRPScene* scene) {
  std::vector<vtkRPSliceNode*> nodes;
  if (!scene) return nodes;
  for (const Preset& preset : Presets) {
    vtkRPSliceNode* node = GetSliceNode(scene, preset.LayoutName);
    if (!node) {
      vtkNew<vtkRPSliceNode> created;
      created->SetLayoutName(preset.LayoutName);
      created->SetName(preset.LayoutName);
      created->SetIDInternal(std::string("vtkRPSliceNode") + preset.LayoutName);
      created->SetOrientation(preset.Orientation);
      node = vtkRPSliceNode::SafeDownCast(scene->AddNode(created));
    }
    if (node) nodes.push_back(node);
  }
  return nodes;
}

void vtkRPSliceNode::JumpAllSlices(vtkRPScene* scene, const double ras[3]) {
  if (!scene) return;
  GetOrAddDefaultSliceNodes(scene);
  for (vtkRPSliceNode* node : GetSliceNodes(scene)) node->JumpSlice(ras);
}

bool vtkRPSliceNode::SetAllSlicesFollow(vtkRPScene* scene, const std::string& nodeID) {
  if (!scene) return false;
  if (!nodeID.empty() && !vtkRPTransformableNode::SafeDownCast(scene->GetNodeByID(nodeID))) return false;
  GetOrAddDefaultSliceNodes(scene);
  bool ok = true;
  for (vtkRPSliceNode* node : GetSliceNodes(scene)) ok = node->SetAndObserveFollowNodeID(nodeID) && ok;
  return ok;
}

// ---------------------------------------------------------------- scene file

void vtkRPSliceNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["layoutName"] = this->GetLayoutName();
  properties["orientation"] = this->Orientation;
  std::ostringstream matrix;
  matrix.precision(17);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) matrix << (r || c ? " " : "") << this->SliceToRAS->GetElement(r, c);
  properties["sliceToRAS"] = matrix.str();
  std::ostringstream fov, origin;
  fov.precision(17);
  origin.precision(17);
  fov << this->FieldOfView[0] << " " << this->FieldOfView[1];
  origin << this->XYOrigin[0] << " " << this->XYOrigin[1];
  properties["fieldOfView"] = fov.str();
  properties["xyOrigin"] = origin.str();
  properties["sliceVisible"] = this->SliceVisible ? "true" : "false";
  properties["foregroundOpacity"] = std::to_string(this->ForegroundOpacity);
  properties["labelOpacity"] = std::to_string(this->LabelOpacity);
}

void vtkRPSliceNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  const int previous = this->StartModify();
  if (auto it = properties.find("layoutName"); it != properties.end()) this->SetLayoutName(it->second);
  if (auto it = properties.find("sliceToRAS"); it != properties.end()) {
    std::istringstream ss(it->second);
    vtkNew<vtkMatrix4x4> m;
    bool ok = true;
    for (int r = 0; r < 4 && ok; ++r)
      for (int c = 0; c < 4 && ok; ++c) {
        double v = 0;
        ok = static_cast<bool>(ss >> v);
        m->SetElement(r, c, v);
      }
    if (ok) this->SetSliceToRAS(m);
  } else if (auto orientation = properties.find("orientation"); orientation != properties.end()) {
    this->SetOrientation(orientation->second);
  }
  auto pair = [&properties](const char* key, double out[2]) {
    auto it = properties.find(key);
    if (it == properties.end()) return false;
    std::istringstream ss(it->second);
    return static_cast<bool>(ss >> out[0] >> out[1]);
  };
  double values[2];
  if (pair("fieldOfView", values)) this->SetFieldOfView(values[0], values[1]);
  if (pair("xyOrigin", values)) this->SetXYOrigin(values[0], values[1]);
  if (auto it = properties.find("sliceVisible"); it != properties.end()) this->SetSliceVisible(it->second == "true");
  if (auto it = properties.find("foregroundOpacity"); it != properties.end())
    this->SetForegroundOpacity(std::atof(it->second.c_str()));
  if (auto it = properties.find("labelOpacity"); it != properties.end()) this->SetLabelOpacity(std::atof(it->second.c_str()));
  this->EndModify(previous);
}
