#include "vtkRPSegmentationNode.h"

#include <algorithm>
#include <cctype>
#include <set>

#include <nlohmann/json.hpp>
#include <vtkObjectFactory.h>
#include <vtkType.h>

vtkStandardNewMacro(vtkRPSegmentationNode);

vtkRPNode* vtkRPSegmentationNode::CreateNodeInstance() { return vtkRPSegmentationNode::New(); }

void vtkRPSegmentationNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  for (const auto& s : this->Segments) {
    os << indent << "Segment " << s.ID << " \"" << s.Name << "\" label " << s.LabelValue << " tissue "
       << s.TissueClass << "\n";
  }
}

int vtkRPSegmentationNode::SetSegment(const Segment& segment) {
  for (size_t i = 0; i < this->Segments.size(); ++i) {
    if (this->Segments[i].ID == segment.ID) {
      this->Segments[i] = segment;
      this->Modified();
      return static_cast<int>(i);
    }
  }
  this->Segments.push_back(segment);
  this->Modified();
  return static_cast<int>(this->Segments.size() - 1);
}

bool vtkRPSegmentationNode::RemoveSegment(const std::string& segmentID) {
  auto it = std::find_if(this->Segments.begin(), this->Segments.end(),
                         [&](const Segment& s) { return s.ID == segmentID; });
  if (it == this->Segments.end()) return false;
  this->Segments.erase(it);
  this->Modified();
  return true;
}

void vtkRPSegmentationNode::RemoveAllSegments() {
  if (this->Segments.empty()) return;
  this->Segments.clear();
  this->Modified();
}

const vtkRPSegmentationNode::Segment* vtkRPSegmentationNode::GetSegmentByID(const std::string& id) const {
  for (const auto& s : this->Segments) {
    if (s.ID == id) return &s;
  }
  return nullptr;
}

const vtkRPSegmentationNode::Segment* vtkRPSegmentationNode::GetSegmentByLabel(int labelValue) const {
  for (const auto& s : this->Segments) {
    if (s.LabelValue == labelValue) return &s;
  }
  return nullptr;
}

const vtkRPSegmentationNode::Segment* vtkRPSegmentationNode::FindSegment(const std::string& reference) const {
  if (const Segment* byID = this->GetSegmentByID(reference)) return byID;
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
  };
  for (const auto& s : this->Segments)
    if (lower(s.Name) == lower(reference)) return &s;
  if (!reference.empty() && reference.size() < 10 && reference.find_first_not_of("0123456789") == std::string::npos)
    return this->GetSegmentByLabel(std::stoi(reference));
  return nullptr;
}

int vtkRPSegmentationNode::GetUnusedLabelValue() const {
  std::set<int> used;
  for (const auto& s : this->Segments) used.insert(s.LabelValue);
  int value = 1;
  while (used.count(value)) ++value;
  return value;
}

void vtkRPSegmentationNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& s : this->Segments) {
    nlohmann::json segment = {{"id", s.ID}, {"name", s.Name}, {"labelValue", s.LabelValue},
                              {"color", {s.Color[0], s.Color[1], s.Color[2]}}, {"tissueClass", s.TissueClass}};
    if (s.Protection.Protected) {
      segment[rp::ProtectedKey] = true;
      segment[rp::SafetyMarginKey] = s.Protection.SafetyMarginMm;
    }
    segments.push_back(segment);
  }
  properties["segments"] = segments.dump();
}

void vtkRPSegmentationNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  auto it = properties.find("segments");
  if (it == properties.end()) return;
  const auto segments = nlohmann::json::parse(it->second, nullptr, false);
  if (!segments.is_array()) return;
  const int previous = this->StartModify();
  this->RemoveAllSegments();
  for (const auto& j : segments) {
    Segment s;
    s.ID = j.value("id", "");
    s.Name = j.value("name", s.ID);
    s.LabelValue = j.value("labelValue", 1);
    s.TissueClass = j.value("tissueClass", "");
    if (j.contains(rp::ProtectedKey) && j[rp::ProtectedKey].is_boolean()) s.Protection.Protected = j[rp::ProtectedKey].get<bool>();
    if (j.contains(rp::SafetyMarginKey) && j[rp::SafetyMarginKey].is_number())
      s.Protection.SafetyMarginMm = std::max(0.0, j[rp::SafetyMarginKey].get<double>());
    if (j.contains("color") && j["color"].is_array() && j["color"].size() == 3) {
      for (int c = 0; c < 3; ++c) s.Color[c] = j["color"][static_cast<size_t>(c)].get<double>();
    }
    this->SetSegment(s);
  }
  this->EndModify(previous);
}

bool vtkRPSegmentationNode::IsLabelScalarType(int vtkType) {
  switch (vtkType) {
    case VTK_CHAR: case VTK_SIGNED_CHAR: case VTK_UNSIGNED_CHAR: case VTK_SHORT: case VTK_UNSIGNED_SHORT:
    case VTK_INT: case VTK_UNSIGNED_INT: case VTK_LONG: case VTK_UNSIGNED_LONG: case VTK_LONG_LONG:
    case VTK_UNSIGNED_LONG_LONG: case VTK_ID_TYPE:
      return true;
    default:
      return false;
  }
}
