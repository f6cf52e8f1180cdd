#include "vtkRPMarkupsNode.h"

#include <sstream>

#include <vtkNew.h>
#include <vtkMatrix4x4.h>

void vtkRPMarkupsNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  for (const auto& p : this->Points) {
    os << indent << p.Label << ": " << p.Position[0] << " " << p.Position[1] << " " << p.Position[2]
       << (p.Selected ? "" : " (unselected)") << (p.Locked ? " (locked)" : "") << "\n";
  }
}

std::string vtkRPMarkupsNode::NextPointID() {
  std::string id;
  bool taken = true;
  while (taken) {
    id = std::to_string(++this->LastPointNumber);
    taken = false;
    for (const auto& p : this->Points) taken |= (p.ID == id);
  }
  return id;
}

std::string vtkRPMarkupsNode::LabelPrefix() const {
  return (this->GetName().empty() ? std::string("F") : this->GetName()) + "-";
}

bool vtkRPMarkupsNode::IsGeneratedLabel(const std::string& label) const {
  const std::string prefix = this->LabelPrefix();
  return label.size() > prefix.size() && label.compare(0, prefix.size(), prefix) == 0 &&
         label.find_first_not_of("0123456789", prefix.size()) == std::string::npos;
}

int vtkRPMarkupsNode::AddControlPoint(const double positionRAS[3], const std::string& label) {
  ControlPoint p;
  p.Label = label;
  for (int i = 0; i < 3; ++i) p.Position[i] = positionRAS[i];
  return this->AddControlPoint(p);
}

int vtkRPMarkupsNode::AddControlPoint(const ControlPoint& point) {
  const int most = this->GetMaximumNumberOfControlPoints();
  if (most >= 0 && this->GetNumberOfControlPoints() >= most) return -1;
  ControlPoint p = point;
  if (p.ID.empty()) p.ID = this->NextPointID();
  if (p.Label.empty()) {
    p.Label = this->LabelPrefix() + std::to_string(this->Points.size() + 1);
  }
  this->Points.push_back(p);
  int index = static_cast<int>(this->Points.size() - 1);
  this->InvokeEvent(PointAddedEvent, &index);
  this->Modified();
  return index;
}

bool vtkRPMarkupsNode::MovePoint(int n, const double positionRAS[3]) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return false;
  ControlPoint& p = this->Points[static_cast<size_t>(n)];
  if (p.Locked) return false;
  for (int i = 0; i < 3; ++i) p.Position[i] = positionRAS[i];
  return true;
}

bool vtkRPMarkupsNode::SetNthControlPointPosition(int n, const double positionRAS[3]) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return false;
  const ControlPoint& p = this->Points[static_cast<size_t>(n)];
  if (p.Locked) return false;
  if (p.Position[0] == positionRAS[0] && p.Position[1] == positionRAS[1] && p.Position[2] == positionRAS[2]) {
    return true;
  }
  this->MovePoint(n, positionRAS);
  this->InvokeEvent(PointModifiedEvent, &n);
  this->Modified();
  return true;
}

bool vtkRPMarkupsNode::SetNthControlPointPositionWorld(int n, const double positionWorld[3]) {
  vtkNew<vtkMatrix4x4> toWorld, fromWorld;
  this->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Invert(toWorld, fromWorld);
  const double in[4] = {positionWorld[0], positionWorld[1], positionWorld[2], 1.0};
  double local[4];
  fromWorld->MultiplyPoint(in, local);
  return this->SetNthControlPointPosition(n, local);
}

void vtkRPMarkupsNode::GetNthControlPointPosition(int n, double positionRAS[3]) const {
  const ControlPoint& p = this->GetNthControlPoint(n);
  for (int i = 0; i < 3; ++i) positionRAS[i] = p.Position[i];
}

void vtkRPMarkupsNode::GetNthControlPointPositionWorld(int n, double positionWorld[3]) const {
  vtkNew<vtkMatrix4x4> toWorld;
  this->GetMatrixTransformToWorld(toWorld);
  const ControlPoint& p = this->GetNthControlPoint(n);
  const double in[4] = {p.Position[0], p.Position[1], p.Position[2], 1.0};
  double out[4];
  toWorld->MultiplyPoint(in, out);
  for (int i = 0; i < 3; ++i) positionWorld[i] = out[i];
}

void vtkRPMarkupsNode::SetNthControlPointLabel(int n, const std::string& label) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return;
  this->Points[static_cast<size_t>(n)].Label = label;
  this->InvokeEvent(PointModifiedEvent, &n);
  this->Modified();
}

void vtkRPMarkupsNode::SetNthControlPointSelected(int n, bool selected) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return;
  this->Points[static_cast<size_t>(n)].Selected = selected;
  this->InvokeEvent(PointModifiedEvent, &n);
  this->Modified();
}

void vtkRPMarkupsNode::SetNthControlPointLocked(int n, bool locked) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return;
  this->Points[static_cast<size_t>(n)].Locked = locked;
  this->InvokeEvent(PointModifiedEvent, &n);
  this->Modified();
}

void vtkRPMarkupsNode::RemoveNthControlPoint(int n) {
  if (n < 0 || n >= this->GetNumberOfControlPoints()) return;
  this->Points.erase(this->Points.begin() + n);
  this->InvokeEvent(PointRemovedEvent, &n);
  this->Modified();
}

void vtkRPMarkupsNode::RemoveAllControlPoints() {
  const int previous = this->StartModify();
  while (!this->Points.empty()) this->RemoveNthControlPoint(this->GetNumberOfControlPoints() - 1);
  this->EndModify(previous);
}

int vtkRPMarkupsNode::GetControlPointIndexByLabel(const std::string& label) const {
  for (size_t i = 0; i < this->Points.size(); ++i) {
    if (this->Points[i].Label == label) return static_cast<int>(i);
  }
  return -1;
}

void vtkRPMarkupsNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  std::ostringstream color;
  color << this->Color[0] << " " << this->Color[1] << " " << this->Color[2];
  properties["color"] = color.str();
}

void vtkRPMarkupsNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  if (auto it = properties.find("color"); it != properties.end()) {
    std::istringstream ss(it->second);
    double c[3];
    if (ss >> c[0] >> c[1] >> c[2]) this->SetColor(c);
  }
}
