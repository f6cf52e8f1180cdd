#include "vtkRPImageNode.h"

#include <cmath>
#include <sstream>

#include <vtkNew.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>

vtkRPImageNode::vtkRPImageNode()
    : ImageData(vtkSmartPointer<vtkImageData>::New()), IJKToRAS(vtkSmartPointer<vtkMatrix4x4>::New()) {}
vtkRPImageNode::~vtkRPImageNode() = default;

void vtkRPImageNode::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  int dims[3];
  this->ImageData->GetDimensions(dims);
  os << indent << "Dimensions: " << dims[0] << " " << dims[1] << " " << dims[2] << "\n";
  os << indent << "IJKToRAS:\n";
  this->IJKToRAS->PrintSelf(os, indent.GetNextIndent());
}

void vtkRPImageNode::SetImageData(vtkImageData* image) {
  this->ImageData = image ? image : vtkSmartPointer<vtkImageData>::New().GetPointer();
  this->ImageData->SetOrigin(0, 0, 0);
  this->ImageData->SetSpacing(1, 1, 1);
  this->Modified();
}

void vtkRPImageNode::SetImageDataKeepGeometry(vtkImageData* image) {
  if (!image) {
    this->SetImageData(nullptr);
    return;
  }
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  const double directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int previous = this->StartModify();
  this->SetImageData(image);
  this->SetGeometry(spacing, origin, directions);
  this->EndModify(previous);
}

void vtkRPImageNode::SetIJKToRASMatrix(const vtkMatrix4x4* ijkToRAS) {
  if (!ijkToRAS) return;
  this->IJKToRAS->DeepCopy(ijkToRAS);
  this->Modified();
}

void vtkRPImageNode::GetRASToIJKMatrix(vtkMatrix4x4* rasToIJK) const { vtkMatrix4x4::Invert(this->IJKToRAS, rasToIJK); }

void vtkRPImageNode::SetGeometry(const double spacing[3], const double originRAS[3], const double directions[3][3]) {
  vtkNew<vtkMatrix4x4> m;
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) m->SetElement(row, col, directions[col][row] * spacing[col]);
  }
  for (int row = 0; row < 3; ++row) m->SetElement(row, 3, originRAS[row]);
  this->SetIJKToRASMatrix(m);
}

void vtkRPImageNode::GetSpacing(double spacing[3]) const {
  for (int col = 0; col < 3; ++col) {
    double s = 0;
    for (int row = 0; row < 3; ++row) s += this->IJKToRAS->GetElement(row, col) * this->IJKToRAS->GetElement(row, col);
    spacing[col] = std::sqrt(s);
  }
}

void vtkRPImageNode::GetOrigin(double originRAS[3]) const {
  for (int row = 0; row < 3; ++row) originRAS[row] = this->IJKToRAS->GetElement(row, 3);
}

void vtkRPImageNode::GetRASBounds(double bounds[6]) const {
  int extent[6];
  this->ImageData->GetExtent(extent);
  bounds[0] = bounds[2] = bounds[4] = VTK_DOUBLE_MAX;
  bounds[1] = bounds[3] = bounds[5] = VTK_DOUBLE_MIN;
  for (int c = 0; c < 8; ++c) {
    const double ijk[4] = {double(extent[(c & 1) ? 1 : 0]), double(extent[(c & 2) ? 3 : 2]),
                           double(extent[(c & 4) ? 5 : 4]), 1.0};
    double ras[4];
    this->IJKToRAS->MultiplyPoint(ijk, ras);
    for (int a = 0; a < 3; ++a) {
      bounds[2 * a] = std::min(bounds[2 * a], ras[a]);
      bounds[2 * a + 1] = std::max(bounds[2 * a + 1], ras[a]);
    }
  }
}

void vtkRPImageNode::WriteProperties(PropertyMap& properties) const {
  this->Superclass::WriteProperties(properties);
  std::ostringstream ss;
  ss.precision(17);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) ss << (i || j ? " " : "") << this->IJKToRAS->GetElement(i, j);
  properties["ijkToRAS"] = ss.str();
}

void vtkRPImageNode::ReadProperties(const PropertyMap& properties) {
  this->Superclass::ReadProperties(properties);
  auto it = properties.find("ijkToRAS");
  if (it == properties.end()) return;
  std::istringstream ss(it->second);
  double e[16];
  for (double& v : e) {
    if (!(ss >> v)) return;
  }
  vtkNew<vtkMatrix4x4> m;
  m->DeepCopy(e);
  this->SetIJKToRASMatrix(m);
}
