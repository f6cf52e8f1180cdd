#include "vtkRPScalarVolumeNode.h"

#include <string>

#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPScalarVolumeNode);

vtkRPNode* vtkRPScalarVolumeNode::CreateNodeInstance() { return vtkRPScalarVolumeNode::New(); }

void vtkRPScalarVolumeNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Window: " << this->Window << "\n" << indent << "Level: " << this->Level << "\n";
}

void vtkRPScalarVolumeNode::SetWindowLevel(double window, double level) {
  const int previous = this->StartModify();
  this->SetWindow(window);
  this->SetLevel(level);
  this->EndModify(previous);
}

void vtkRPScalarVolumeNode::SetWindowLevelFromScalarRange() {
  if (!this->GetImageData() || !this->GetImageData()->GetPointData()->GetScalars()) return;
  double range[2];
  this->GetImageData()->GetScalarRange(range);
  this->SetWindowLevel(std::max(range[1] - range[0], 1e-6), 0.5 * (range[0] + range[1]));
}

void vtkRPScalarVolumeNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["window"] = std::to_string(this->Window);
  properties["level"] = std::to_string(this->Level);
}

void vtkRPScalarVolumeNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("window"); it != properties.end()) this->SetWindow(std::atof(it->second.c_str()));
  if (auto it = properties.find("level"); it != properties.end()) this->SetLevel(std::atof(it->second.c_str()));
}
