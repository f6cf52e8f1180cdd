#include "rpImageVolume.h"

#include <cmath>

#include "vtkRPImageNode.h"
#include "vtkRPScalarVolumeNode.h"

namespace rp {

void ImageVolume::GetSpacing(double spacing[3]) const {
  for (int c = 0; c < 3; ++c) {
    double s = 0.0;
    for (int r = 0; r < 3; ++r) s += this->IJKToRAS->GetElement(r, c) * this->IJKToRAS->GetElement(r, c);
    spacing[c] = std::sqrt(s);
  }
}

void ImageVolume::IndexToRAS(const double ijk[3], double ras[3]) const {
  const double in[4] = {ijk[0], ijk[1], ijk[2], 1.0};
  double out[4];
  this->IJKToRAS->MultiplyPoint(in, out);
  for (int a = 0; a < 3; ++a) ras[a] = out[a];
}

void CopyToNode(const ImageVolume& volume, vtkRPImageNode* node) {
  if (!node) return;
  const int previous = node->StartModify();
  node->SetImageData(volume.Image);
  node->SetIJKToRASMatrix(volume.IJKToRAS);
  node->EndModify(previous);
}

void CopyToNode(const ImageVolume& volume, vtkRPScalarVolumeNode* node) {
  if (!node) return;
  const int previous = node->StartModify();
  CopyToNode(volume, static_cast<vtkRPImageNode*>(node));
  if (volume.Window > 0.0) {
    node->SetWindowLevel(volume.Window, volume.Level);
  } else {
    node->SetWindowLevelFromScalarRange();
  }
  node->EndModify(previous);
}

ImageVolume FromNode(vtkRPImageNode* node) {
  ImageVolume volume;
  if (!node) return volume;
  volume.Image = node->GetImageData();
  volume.IJKToRAS->DeepCopy(node->GetIJKToRASMatrix());
  if (auto* scalar = vtkRPScalarVolumeNode::SafeDownCast(node)) {
    volume.Window = scalar->GetWindow();
    volume.Level = scalar->GetLevel();
  }
  return volume;
}

}  // namespace rp
