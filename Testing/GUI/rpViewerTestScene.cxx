#include "rpViewerTestScene.h"

#include <cmath>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkShortArray.h>
#include <vtkPointData.h>
#include <vtkSphereSource.h>

#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace rp::test {

vtkSmartPointer<vtkRPScalarVolumeNode> MakeVolume() {
  vtkNew<vtkImageData> image;
  image->SetDimensions(Dimensions[0], Dimensions[1], Dimensions[2]);
  image->AllocateScalars(VTK_SHORT, 1);
  double origin[3];
  for (int a = 0; a < 3; ++a) origin[a] = Center[a] - 0.5 * (Dimensions[a] - 1) * Spacing[a];
  auto* voxels = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < Dimensions[2]; ++k) {
    for (int j = 0; j < Dimensions[1]; ++j) {
      for (int i = 0; i < Dimensions[0]; ++i) {
        const double p[3] = {origin[0] + i * Spacing[0], origin[1] + j * Spacing[1], origin[2] + k * Spacing[2]};
        const double d = std::sqrt((p[0] - Center[0]) * (p[0] - Center[0]) + (p[1] - Center[1]) * (p[1] - Center[1]) +
                                   (p[2] - Center[2]) * (p[2] - Center[2]));
        // Soft tissue (40 HU) rising 4 HU per slice along S, a 1000 HU ball in the middle.
        *voxels++ = static_cast<short>(d < BallRadius ? 1000 : 40 + 4 * k);
      }
    }
  }
  auto volume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  volume->SetName("SyntheticCT");
  volume->SetImageData(image);
  const double directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  volume->SetGeometry(Spacing, origin, directions);
  volume->SetWindowLevel(2000, 500);
  return volume;
}

vtkSmartPointer<vtkRPModelNode> MakeSphereModel() {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(ModelCenter[0], ModelCenter[1], ModelCenter[2]);
  sphere->SetRadius(SphereRadius);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(64);
  sphere->Update();
  auto model = vtkSmartPointer<vtkRPModelNode>::New();
  model->SetName("Femur");
  model->SetPolyData(sphere->GetOutput());
  model->SetColor(0.9, 0.85, 0.6);
  model->SetTissueClass("bone");
  return model;
}

void AddVolumeAndModel(vtkRPScene* scene) {
  scene->AddNode(MakeVolume());
  scene->AddNode(MakeSphereModel());
}

}  // namespace rp::test
