#include "vtkRPLayoutNode.h"

#include <vtkObjectFactory.h>

#include "vtkRPScene.h"

vtkStandardNewMacro(vtkRPLayoutNode);

namespace {
const char* const ArrangementNames[] = {"4up", "3d", "axial", "sagittal", "coronal"};
const char* const LayoutTag = "Layout";
}  // namespace

vtkRPLayoutNode::vtkRPLayoutNode() { this->SetSingletonTag(LayoutTag); }

vtkRPNode* vtkRPLayoutNode::CreateNodeInstance() { return vtkRPLayoutNode::New(); }

void vtkRPLayoutNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ViewArrangement: " << GetArrangementAsString(this->ViewArrangement) << "\n";
}

const char* vtkRPLayoutNode::GetArrangementAsString(int arrangement) {
  if (arrangement < FourUp || arrangement > OneUpCoronal) return "unknown";
  return ArrangementNames[arrangement];
}

int vtkRPLayoutNode::GetArrangementFromString(const std::string& text) {
  for (int i = FourUp; i <= OneUpCoronal; ++i) {
    if (text == ArrangementNames[i]) return i;
  }
  return -1;
}

void vtkRPLayoutNode::SetViewArrangement(int arrangement) {
  if (arrangement < FourUp || arrangement > OneUpCoronal || arrangement == this->ViewArrangement) return;
  this->ViewArrangement = arrangement;
  this->Modified();
}

vtkRPLayoutNode* vtkRPLayoutNode::GetOrAddLayoutNode(vtkRPScene* scene) {
  if (!scene) return nullptr;
  if (auto* existing = vtkRPLayoutNode::SafeDownCast(scene->GetSingletonNode(LayoutTag, "vtkRPLayoutNode"))) {
    return existing;
  }
  vtkNew<vtkRPLayoutNode> created;
  created->SetName(LayoutTag);
  created->SetIDInternal("vtkRPLayoutNodeLayout");
  return vtkRPLayoutNode::SafeDownCast(scene->AddNode(created));
}

void vtkRPLayoutNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["viewArrangement"] = GetArrangementAsString(this->ViewArrangement);
}

void vtkRPLayoutNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("viewArrangement"); it != properties.end()) {
    this->SetViewArrangement(GetArrangementFromString(it->second));
  }
}
