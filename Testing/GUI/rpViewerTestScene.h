#pragma once
// A small synthetic scene with known geometry for the viewer tests: a CT-like volume (a bright
// ball in soft tissue, a gradient along S) off the RAS origin, and a sphere model.
#include <vtkSmartPointer.h>

class vtkRPModelNode;
class vtkRPScalarVolumeNode;
class vtkRPScene;

namespace rp::test {

// Volume: 48 x 40 x 32 voxels, spacing 2 x 2 x 2.5 mm, axis-aligned RAS, centre at Center.
constexpr int Dimensions[3] = {48, 40, 32};
constexpr double Spacing[3] = {2.0, 2.0, 2.5};
constexpr double Center[3] = {10.0, -5.0, 20.0};
constexpr double BallRadius = 25.0;   // bone-bright ball (1000 HU) at Center
constexpr double SphereRadius = 20.0;  // the model: a sphere at ModelCenter
constexpr double ModelCenter[3] = {18.0, -5.0, 20.0};

vtkSmartPointer<vtkRPScalarVolumeNode> MakeVolume();
vtkSmartPointer<vtkRPModelNode> MakeSphereModel();
/// Adds both to the scene; returns nothing (nodes are found by class).
void AddVolumeAndModel(vtkRPScene* scene);

}  // namespace rp::test
