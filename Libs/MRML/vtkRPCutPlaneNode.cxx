#include "vtkRPCutPlaneNode.h"

#include <cmath>

#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>

#include "rpPropertyText.h"

vtkStandardNewMacro(vtkRPCutPlaneNode);

namespace {
bool Finite(const double v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// `v` minus its component along the unit `n`, normalised; false when (nearly) along n.
bool InPlaneUnit(const double v[3], const double n[3], double out[3]) {
  const double along = vtkMath::Dot(v, n);
  for (int i = 0; i < 3; ++i) out[i] = v[i] - along * n[i];
  const double length = vtkMath::Norm(out);
  if (!(length > 1e-9 * std::max(1.0, vtkMath::Norm(v)))) return false;
  for (int i = 0; i < 3; ++i) out[i] /= length;
  return true;
}
}  // namespace

vtkRPCutPlaneNode::vtkRPCutPlaneNode() {
  const double orange[3] = {0.95, 0.6, 0.15};
  this->SetColor(orange);
}

vtkRPNode* vtkRPCutPlaneNode::CreateNodeInstance() { return vtkRPCutPlaneNode::New(); }

void vtkRPCutPlaneNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Normal: " << this->Normal[0] << " " << this->Normal[1] << " " << this->Normal[2] << "\n"
     << indent << "XAxis: " << this->XAxis[0] << " " << this->XAxis[1] << " " << this->XAxis[2] << "\n"
     << indent << "Size: " << this->Size[0] << " x " << this->Size[1] << " mm\n";
}

bool vtkRPCutPlaneNode::SetOrigin(const double originRAS[3]) {
  if (!Finite(originRAS)) return false;
  if (this->GetNumberOfControlPoints() == 0) return this->AddControlPoint(originRAS, "origin") >= 0;
  return this->SetNthControlPointPosition(0, originRAS);
}

bool vtkRPCutPlaneNode::GetOrigin(double originRAS[3]) const {
  if (!this->IsComplete()) return false;
  this->GetNthControlPointPosition(0, originRAS);
  return true;
}

bool vtkRPCutPlaneNode::GetOriginWorld(double originWorld[3]) const {
  if (!this->IsComplete()) return false;
  this->GetNthControlPointPositionWorld(0, originWorld);
  return true;
}

bool vtkRPCutPlaneNode::SetNormal(const double normal[3]) {
  double n[3] = {normal[0], normal[1], normal[2]};
  if (!Finite(n) || !(vtkMath::Normalize(n) > 0)) return false;
  double x[3];
  if (!InPlaneUnit(this->XAxis, n, x)) {
    // The old x axis lies along the new normal: take the old normal's in-plane part instead (the
    // plane turned by a right angle about y keeps its y axis).
    if (!InPlaneUnit(this->Normal, n, x)) vtkMath::Perpendiculars(n, x, nullptr, 0);
  }
  if (n[0] == this->Normal[0] && n[1] == this->Normal[1] && n[2] == this->Normal[2]) return true;
  for (int i = 0; i < 3; ++i) this->Normal[i] = n[i], this->XAxis[i] = x[i];
  this->Modified();
  return true;
}

void vtkRPCutPlaneNode::GetNormal(double normal[3]) const {
  for (int i = 0; i < 3; ++i) normal[i] = this->Normal[i];
}

bool vtkRPCutPlaneNode::SetXAxis(const double xAxis[3]) {
  double x[3];
  if (!Finite(xAxis) || !InPlaneUnit(xAxis, this->Normal, x)) return false;
  if (x[0] == this->XAxis[0] && x[1] == this->XAxis[1] && x[2] == this->XAxis[2]) return true;
  for (int i = 0; i < 3; ++i) this->XAxis[i] = x[i];
  this->Modified();
  return true;
}

void vtkRPCutPlaneNode::GetXAxis(double xAxis[3]) const {
  for (int i = 0; i < 3; ++i) xAxis[i] = this->XAxis[i];
}

void vtkRPCutPlaneNode::GetYAxis(double yAxis[3]) const { vtkMath::Cross(this->Normal, this->XAxis, yAxis); }

void vtkRPCutPlaneNode::GetNormalWorld(double normal[3]) const {
  vtkNew<vtkMatrix4x4> toWorld, inverse;
  this->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Invert(toWorld, inverse);
  // A normal maps by the inverse transpose (right under scaling and shear too).
  for (int r = 0; r < 3; ++r) {
    normal[r] = 0;
    for (int c = 0; c < 3; ++c) normal[r] += inverse->GetElement(c, r) * this->Normal[c];
  }
  vtkMath::Normalize(normal);
}

void vtkRPCutPlaneNode::GetXAxisWorld(double xAxis[3]) const {
  vtkNew<vtkMatrix4x4> toWorld;
  this->GetMatrixTransformToWorld(toWorld);
  for (int r = 0; r < 3; ++r) {
    xAxis[r] = 0;
    for (int c = 0; c < 3; ++c) xAxis[r] += toWorld->GetElement(r, c) * this->XAxis[c];
  }
  vtkMath::Normalize(xAxis);
}

void vtkRPCutPlaneNode::SetSize(double x, double y) {
  if (!(x > 0) || !(y > 0) || !std::isfinite(x) || !std::isfinite(y)) return;
  if (x == this->Size[0] && y == this->Size[1]) return;
  this->Size[0] = x;
  this->Size[1] = y;
  this->Modified();
}

void vtkRPCutPlaneNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  properties["normal"] = rp::FormatPropertyNumbers(this->Normal, 3);
  properties["xAxis"] = rp::FormatPropertyNumbers(this->XAxis, 3);
  properties["sizeMm"] = rp::FormatPropertyNumbers(this->Size, 2);
}

void vtkRPCutPlaneNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  std::vector<double> v;
  const int previous = this->StartModify();
  if (auto it = properties.find("normal"); it != properties.end() && rp::ParsePropertyNumbers(it->second, v, 3))
    this->SetNormal(v.data());
  if (auto it = properties.find("xAxis"); it != properties.end() && rp::ParsePropertyNumbers(it->second, v, 3))
    this->SetXAxis(v.data());
  if (auto it = properties.find("sizeMm"); it != properties.end() && rp::ParsePropertyNumbers(it->second, v, 2))
    this->SetSize(v[0], v[1]);
  this->EndModify(previous);
}
