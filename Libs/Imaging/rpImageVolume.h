#pragma once
// A scalar volume as the imaging code passes it around before it becomes a scene node:
// the voxels (vtkImageData with origin 0, spacing 1, Slicer's convention) and the IJK-to-RAS
// matrix that carries spacing, directions and origin. Bridges to vtkRPScalarVolumeNode.
#include <string>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

class vtkRPImageNode;
class vtkRPScalarVolumeNode;

namespace rp {

struct ImageVolume {
  vtkSmartPointer<vtkImageData> Image;  // one scalar component; origin 0, spacing 1
  vtkSmartPointer<vtkMatrix4x4> IJKToRAS = vtkSmartPointer<vtkMatrix4x4>::New();
  double Window = 0.0;  // display window (0 = unknown)
  double Level = 0.0;
  std::string Modality;  // "CT", "MR", "SEG" or "" when unknown
  std::string Description;

  bool Empty() const { return !this->Image || this->Image->GetNumberOfPoints() == 0; }
  void GetSpacing(double spacing[3]) const;  // column norms of IJKToRAS
  /// RAS position of voxel (i, j, k) (continuous index).
  void IndexToRAS(const double ijk[3], double ras[3]) const;
};

/// Copies image + geometry (+ window/level when known) into a node (the node takes the image).
void CopyToNode(const ImageVolume& volume, vtkRPImageNode* node);
void CopyToNode(const ImageVolume& volume, vtkRPScalarVolumeNode* node);
/// Shallow view of a node as an ImageVolume (shares the image, copies the matrix).
ImageVolume FromNode(vtkRPImageNode* node);

}  // namespace rp
