#include "vtkRPScrewNode.h"

#include <cmath>

#include <vtkObjectFactory.h>

#include "rpPropertyText.h"

vtkStandardNewMacro(vtkRPScrewNode);

vtkRPScrewNode::vtkRPScrewNode() {
  const double metal[3] = {0.75, 0.78, 0.85};
  this->SetColor(metal);
}

vtkRPNode* vtkRPScrewNode::CreateNodeInstance() { return vtkRPScrewNode::New(); }

void vtkRPScrewNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Screw: " << this->ScrewDiameterMm << " x " << this->ScrewLengthMm << " mm, head "
     << this->HeadDiameterMm << " x " << this->HeadLengthMm << " mm\n";
}

void vtkRPScrewNode::SetSize(double& field, double mm, bool mayBeZero) {
  if (!std::isfinite(mm) || mm < 0 || (mm == 0 && !mayBeZero) || mm == field) return;
  field = mm;
  this->Modified();
}

void vtkRPScrewNode::SetScrewDiameterMm(double mm) { this->SetSize(this->ScrewDiameterMm, mm, false); }
void vtkRPScrewNode::SetScrewLengthMm(double mm) { this->SetSize(this->ScrewLengthMm, mm, false); }
void vtkRPScrewNode::SetHeadDiameterMm(double mm) { this->SetSize(this->HeadDiameterMm, mm, false); }
void vtkRPScrewNode::SetHeadLengthMm(double mm) { this->SetSize(this->HeadLengthMm, mm, true); }

void vtkRPScrewNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["screwDiameterMm"] = rp::FormatPropertyNumber(this->ScrewDiameterMm);
  properties["screwLengthMm"] = rp::FormatPropertyNumber(this->ScrewLengthMm);
  properties["headDiameterMm"] = rp::FormatPropertyNumber(this->HeadDiameterMm);
  properties["headLengthMm"] = rp::FormatPropertyNumber(this->HeadLengthMm);
}

void vtkRPScrewNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  const std::pair<const char*, void (vtkRPScrewNode::*)(double)> fields[] = {
      {"screwDiameterMm", &vtkRPScrewNode::SetScrewDiameterMm},
      {"screwLengthMm", &vtkRPScrewNode::SetScrewLengthMm},
      {"headDiameterMm", &vtkRPScrewNode::SetHeadDiameterMm},
      {"headLengthMm", &vtkRPScrewNode::SetHeadLengthMm}};
  for (const auto& [key, set] : fields) {
    double value = 0;
    if (auto it = properties.find(key); it != properties.end() && rp::ParsePropertyNumber(it->second, value))
      (this->*set)(value);
  }
}
