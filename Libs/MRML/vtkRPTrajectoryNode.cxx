#include "vtkRPTrajectoryNode.h"

#include <cmath>

#include <vtkMath.h>
#include <vtkObjectFactory.h>

#include "rpPropertyText.h"

vtkStandardNewMacro(vtkRPTrajectoryNode);

vtkRPTrajectoryNode::vtkRPTrajectoryNode() {
  const double green[3] = {0.2, 0.8, 0.3};
  this->SetColor(green);
}

vtkRPNode* vtkRPTrajectoryNode::CreateNodeInstance() { return vtkRPTrajectoryNode::New(); }

void vtkRPTrajectoryNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ToolDiameterMm: " << this->ToolDiameterMm << "\n"
     << indent << "IntendedTissue: " << this->IntendedTissue << "\n";
}

void vtkRPTrajectoryNode::SetEntryAndTarget(const double entryRAS[3], const double targetRAS[3]) {
  const int previous = this->StartModify();
  this->SetEntry(entryRAS);
  this->SetTarget(targetRAS);
  this->EndModify(previous);
}

bool vtkRPTrajectoryNode::SetEnd(int index, const double positionRAS[3]) {
  const int previous = this->StartModify();
  bool ok = true;
  while (ok && this->GetNumberOfControlPoints() <= index) {
    const std::string label = this->GetNumberOfControlPoints() == EntryIndex ? "entry" : "target";
    ok = this->AddControlPoint(positionRAS, label) >= 0;
  }
  ok = ok && this->SetNthControlPointPosition(index, positionRAS);
  this->EndModify(previous);
  return ok;
}

bool vtkRPTrajectoryNode::SetEntry(const double entryRAS[3]) { return this->SetEnd(EntryIndex, entryRAS); }
bool vtkRPTrajectoryNode::SetTarget(const double targetRAS[3]) { return this->SetEnd(TargetIndex, targetRAS); }

bool vtkRPTrajectoryNode::GetEntry(double entryRAS[3]) const {
  if (this->GetNumberOfControlPoints() <= EntryIndex) return false;
  this->GetNthControlPointPosition(EntryIndex, entryRAS);
  return true;
}

bool vtkRPTrajectoryNode::GetTarget(double targetRAS[3]) const {
  if (this->GetNumberOfControlPoints() <= TargetIndex) return false;
  this->GetNthControlPointPosition(TargetIndex, targetRAS);
  return true;
}

bool vtkRPTrajectoryNode::GetEntryWorld(double entryWorld[3]) const {
  if (this->GetNumberOfControlPoints() <= EntryIndex) return false;
  this->GetNthControlPointPositionWorld(EntryIndex, entryWorld);
  return true;
}

bool vtkRPTrajectoryNode::GetTargetWorld(double targetWorld[3]) const {
  if (this->GetNumberOfControlPoints() <= TargetIndex) return false;
  this->GetNthControlPointPositionWorld(TargetIndex, targetWorld);
  return true;
}

double vtkRPTrajectoryNode::GetLengthMm() const {
  double entry[3], target[3];
  if (!this->GetEntryWorld(entry) || !this->GetTargetWorld(target)) return 0.0;
  return std::sqrt(vtkMath::Distance2BetweenPoints(entry, target));
}

void vtkRPTrajectoryNode::SetToolDiameterMm(double diameter) {
  if (!(diameter > 0) || !std::isfinite(diameter) || diameter == this->ToolDiameterMm) return;
  this->ToolDiameterMm = diameter;
  this->Modified();
}

void vtkRPTrajectoryNode::SetIntendedTissue(const std::string& tissue) {
  if (tissue == this->IntendedTissue) return;
  this->IntendedTissue = tissue;
  this->Modified();
}

void vtkRPTrajectoryNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["toolDiameterMm"] = rp::FormatPropertyNumber(this->ToolDiameterMm);
  properties["intendedTissue"] = this->IntendedTissue;
}

void vtkRPTrajectoryNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  double value = 0;
  if (auto it = properties.find("toolDiameterMm"); it != properties.end() && rp::ParsePropertyNumber(it->second, value))
    this->SetToolDiameterMm(value);
  if (auto it = properties.find("intendedTissue"); it != properties.end()) this->SetIntendedTissue(it->second);
}
