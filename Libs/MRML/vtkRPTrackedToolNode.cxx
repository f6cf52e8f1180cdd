#include "vtkRPTrackedToolNode.h"

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPTrackedToolNode);

vtkRPNode* vtkRPTrackedToolNode::CreateNodeInstance() { return vtkRPTrackedToolNode::New(); }

const char* vtkRPTrackedToolNode::GetStatusAsString(int status) {
  switch (status) {
    case StatusOK: return "OK";
    case StatusMissing: return "MISSING";
    case StatusOutOfVolume: return "OUT_OF_VOLUME";
    case StatusStale: return "STALE";
    case StatusDisabled: return "DISABLED";
    default: return "UNKNOWN";
  }
}

int vtkRPTrackedToolNode::GetStatusFromString(const std::string& text) {
  for (int s = StatusUnknown; s <= StatusDisabled; ++s) {
    if (text == GetStatusAsString(s)) return s;
  }
  return StatusUnknown;
}

void vtkRPTrackedToolNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Status: " << GetStatusAsString(this->Status) << "\n"
     << indent << "Timestamp: " << this->Timestamp << "\n"
     << indent << "ErrorRMS: " << this->ErrorRMS << "\n";
}

void vtkRPTrackedToolNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["status"] = GetStatusAsString(this->Status);
  properties["timestamp"] = std::to_string(this->Timestamp);
  properties["errorRMS"] = std::to_string(this->ErrorRMS);
}

void vtkRPTrackedToolNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("status"); it != properties.end()) this->SetStatus(GetStatusFromString(it->second));
  if (auto it = properties.find("timestamp"); it != properties.end()) this->SetTimestamp(std::atof(it->second.c_str()));
  if (auto it = properties.find("errorRMS"); it != properties.end()) this->SetErrorRMS(std::atof(it->second.c_str()));
}
