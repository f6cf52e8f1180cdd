#include "vtkRPModelNode.h"

#include <sstream>

#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkRPModelNode);

vtkRPModelNode::vtkRPModelNode() : PolyData(vtkSmartPointer<vtkPolyData>::New()) {}
vtkRPModelNode::~vtkRPModelNode() = default;

vtkRPNode* vtkRPModelNode::CreateNodeInstance() { return vtkRPModelNode::New(); }

void vtkRPModelNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Points: " << this->PolyData->GetNumberOfPoints() << " Cells: " << this->PolyData->GetNumberOfCells()
     << "\n"
     << indent << "TissueClass: " << this->TissueClass << " Haptic: " << this->Haptic << "\n";
  if (this->Protection.Protected) os << indent << "Protected, safety margin " << this->Protection.SafetyMarginMm << " mm\n";
}

void vtkRPModelNode::SetPolyData(vtkPolyData* polyData) {
  this->PolyData = polyData ? polyData : vtkSmartPointer<vtkPolyData>::New().GetPointer();
  this->Modified();
}

void vtkRPModelNode::SetTissueClass(const std::string& tissueClass) {
  if (tissueClass == this->TissueClass) return;
  this->TissueClass = tissueClass;
  this->Modified();
}

void vtkRPModelNode::SetProtection(const rp::StructureProtection& protection) {
  if (protection == this->Protection) return;
  this->Protection = protection;
  this->Modified();
}

void vtkRPModelNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  std::ostringstream color;
  color << this->Color[0] << " " << this->Color[1] << " " << this->Color[2];
  properties["color"] = color.str();
  properties["opacity"] = std::to_string(this->Opacity);
  properties["visibility"] = this->Visibility ? "true" : "false";
  // Written only when off, so that scenes of models drawn on the slices (all before) stay as they were.
  if (!this->SliceIntersectionVisibility) properties["sliceIntersectionVisibility"] = "false";
  properties["haptic"] = this->Haptic ? "true" : "false";
  properties["tissueClass"] = this->TissueClass;
  rp::WriteProtection(this->Protection, properties, rp::ProtectedKey, rp::SafetyMarginKey);
}

void vtkRPModelNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("color"); it != properties.end()) {
    std::istringstream ss(it->second);
    double c[3];
    if (ss >> c[0] >> c[1] >> c[2]) this->SetColor(c);
  }
  if (auto it = properties.find("opacity"); it != properties.end()) this->SetOpacity(std::atof(it->second.c_str()));
  if (auto it = properties.find("visibility"); it != properties.end()) this->SetVisibility(it->second == "true");
  if (auto it = properties.find("haptic"); it != properties.end()) this->SetHaptic(it->second == "true");
  this->SetSliceIntersectionVisibility(properties.count("sliceIntersectionVisibility") == 0 ||
                                       properties.at("sliceIntersectionVisibility") == "true");
  if (auto it = properties.find("tissueClass"); it != properties.end()) this->SetTissueClass(it->second);
  this->SetProtection(rp::ReadProtection(properties, rp::ProtectedKey, rp::SafetyMarginKey));
}
