#include "vtkRPPlanNode.h"

void vtkRPPlanNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  if (!this->PlannedOn.empty()) os << indent << "PlannedOn: " << this->PlannedOn << "\n";
}

void vtkRPPlanNode::SetPlannedOn(const std::string& identity) {
  if (identity == this->PlannedOn) return;
  this->PlannedOn = identity;
  this->Modified();
}

void vtkRPPlanNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  if (!this->PlannedOn.empty()) properties["plannedOn"] = this->PlannedOn;
}

void vtkRPPlanNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("plannedOn"); it != properties.end()) this->SetPlannedOn(it->second);
}
