// Re-slicing against an analytic volume and a real knee CT's labels (the slice frames are the
// scene's, vtkRPSliceNode), and tip-to-surface distance against a sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>

#include "rpVolumeIO.h"
#include "rpSharedData.h"
#include "rpVolumeReslice.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"

namespace {
// Intensity linear in RAS: f(R,A,S) = 2R + 3A + 5S + 7. Trilinear interpolation reproduces a
// linear field exactly, so every resliced pixel has a closed-form value.
double Field(const double ras[3]) { return 2 * ras[0] + 3 * ras[1] + 5 * ras[2] + 7; }

vtkSmartPointer<vtkRPScalarVolumeNode> MakeLinearVolume() {
  auto volume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  const double c = std::cos(0.4), s = std::sin(0.4);
  const double spacing[3] = {1.0, 1.25, 2.0}, origin[3] = {-30, -25, -40};
  const double directions[3][3] = {{c, s, 0}, {-s, c, 0}, {0, 0, 1}};
  volume->SetGeometry(spacing, origin, directions);
  vtkNew<vtkImageData> image;
  image->SetDimensions(60, 50, 40);
  image->AllocateScalars(VTK_DOUBLE, 1);
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 50; ++j)
      for (int i = 0; i < 60; ++i) {
        const double ijk[4] = {double(i), double(j), double(k), 1}, ras[4] = {0, 0, 0, 0};
        double out[4];
        volume->GetIJKToRASMatrix()->MultiplyPoint(ijk, out);
        (void)ras;
        *static_cast<double*>(image->GetScalarPointer(i, j, k)) = Field(out);
      }
  volume->SetImageData(image);
  return volume;
}
}  // namespace

TEST(Reslice, AxialSagittalCoronalAndToolPlaneSampleTheAnalyticField) {
  auto volume = MakeLinearVolume();
  const double center[3] = {-5.5, 3.25, 1.0};
  rp::ResliceOptions options;
  options.FieldOfView[0] = options.FieldOfView[1] = 20;
  options.Spacing = 0.5;
  vtkNew<vtkMatrix4x4> toolTipToRAS;  // a tool tilted 30° about R
  const double a = 30 * M_PI / 180;
  toolTipToRAS->SetElement(1, 1, std::cos(a));
  toolTipToRAS->SetElement(1, 2, -std::sin(a));
  toolTipToRAS->SetElement(2, 1, std::sin(a));
  toolTipToRAS->SetElement(2, 2, std::cos(a));
  for (int r = 0; r < 3; ++r) toolTipToRAS->SetElement(r, 3, center[r]);
  const char* orientations[3] = {"Axial", "Sagittal", "Coronal"};
  for (int o = 0; o < 4; ++o) {
    vtkNew<vtkMatrix4x4> sliceToRAS;
    if (o < 3) {
      ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS(orientations[o], center, sliceToRAS));
    } else {
      vtkRPSliceNode::ComputeSliceToRASForTool(toolTipToRAS, sliceToRAS);
    }
    auto slice = rp::ResliceVolume(volume, sliceToRAS, options);
    int dims[3];
    slice->GetDimensions(dims);
    ASSERT_EQ(dims[0], 40);
    ASSERT_EQ(dims[2], 1);
    double origin[3], spacing[3];
    slice->GetOrigin(origin);
    slice->GetSpacing(spacing);
    double maxError = 0;
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const double p[4] = {origin[0] + i * spacing[0], origin[1] + j * spacing[1], 0, 1};
        double ras[4];
        sliceToRAS->MultiplyPoint(p, ras);
        maxError = std::max(maxError, std::abs(slice->GetScalarComponentAsDouble(i, j, 0, 0) - Field(ras)));
      }
    // vtkImageReslice computes interpolation weights in single precision: ~1e-7 relative.
    EXPECT_LT(maxError, 1e-3) << "orientation " << o;
  }
}

namespace {
// Centroid (pixel coordinates) of the pixels of one label in a re-sliced labelmap.
bool LabelCentroid(vtkImageData* slice, int label, double centroid[2]) {
  int dims[3];
  slice->GetDimensions(dims);
  double sum[2] = {0, 0};
  int count = 0;
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i) {
      if (std::lround(slice->GetScalarComponentAsDouble(i, j, 0, 0)) != label) continue;
      sum[0] += i;
      sum[1] += j;
      ++count;
    }
  if (count < 10) return false;
  centroid[0] = sum[0] / count;
  centroid[1] = sum[1] / count;
  return true;
}
}  // namespace

// A case whose answer anatomy gives: the Visible Human Female's RIGHT knee. The fibula is
// lateral to the tibia, i.e. towards the patient's right, so in the radiological axial and
// coronal views (patient's right on screen LEFT) the fibula lies left of the tibia; the labels
// were drawn on the real CT by others (../shared/data/knee-ct-vhf).
TEST(Reslice, RightKneeFibulaIsOnTheScreensLeftInAxialAndCoronal) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/labels.nrrd");
  const std::string path = rptest::SharedDataPath("knee-ct-vhf/labels.nrrd");
  vtkNew<vtkRPScalarVolumeNode> labels;  // the labelmap as plain voxels
  std::string error;
  ASSERT_TRUE(rp::ReadVolumeFile(path, labels, error)) << error;
  double bounds[6];
  labels->GetRASBounds(bounds);
  // 30 mm below the top of the crop: through the fibular head and the tibial plateau.
  const double point[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), bounds[5] - 30};
  rp::ResliceOptions options;
  options.FieldOfView[0] = options.FieldOfView[1] = 200;
  options.Spacing = 1.0;
  options.Linear = false;
  // Axial: one slice through both bones.
  vtkNew<vtkMatrix4x4> axialToRAS;
  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Axial", point, axialToRAS));
  auto axial = rp::ResliceVolume(labels, axialToRAS, options);
  double tibia[2], fibula[2];
  ASSERT_TRUE(LabelCentroid(axial, 1, tibia));
  ASSERT_TRUE(LabelCentroid(axial, 2, fibula));
  EXPECT_LT(fibula[0], tibia[0] - 10) << "axial: the right fibula must be on the screen's left";
  EXPECT_LT(fibula[1], tibia[1] - 10) << "axial: anterior is up, the fibula lies behind the tibia";

  // Coronal: the fibula's head lies behind the tibia, so each bone is cut through its own
  // centre; both planes share R and S, so their pictures share the screen's x axis.
  double origin[3], spacing[3], boneA[2];
  axial->GetOrigin(origin);
  axial->GetSpacing(spacing);
  const double* centres[2] = {tibia, fibula};
  for (int bone = 0; bone < 2; ++bone) {
    const double inPlane[4] = {origin[0] + centres[bone][0] * spacing[0], origin[1] + centres[bone][1] * spacing[1], 0, 1};
    double ras[4];
    axialToRAS->MultiplyPoint(inPlane, ras);
    boneA[bone] = ras[1];
  }
  double coronalX[2];
  for (int bone = 0; bone < 2; ++bone) {
    const double through[3] = {point[0], boneA[bone], point[2]};
    vtkNew<vtkMatrix4x4> coronalToRAS;
    ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Coronal", through, coronalToRAS));
    auto coronal = rp::ResliceVolume(labels, coronalToRAS, options);
    double centroid[2];
    ASSERT_TRUE(LabelCentroid(coronal, bone + 1, centroid)) << "bone " << bone + 1;
    coronalX[bone] = centroid[0];
  }
  EXPECT_LT(coronalX[1], coronalX[0] - 10) << "coronal: the right fibula must be on the screen's left";
  // Sagittal: superior is up; the tibia's top (the plateau) is above its centre in the picture.
  vtkNew<vtkMatrix4x4> sagittal;
  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Sagittal", point, sagittal));
  EXPECT_DOUBLE_EQ(sagittal->GetElement(2, 1), 1.0);
}

TEST(Reslice, FollowsTheVolumesParentTransform) {
  vtkNew<vtkRPScene> scene;
  auto volume = MakeLinearVolume();
  vtkNew<vtkRPLinearTransformNode> shift;
  scene->AddNode(volume);
  scene->AddNode(shift);
  const double m[16] = {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  shift->SetMatrixTransformToParent(m);
  volume->SetAndObserveTransformNodeID(shift->GetID());
  const double center[3] = {5, 0, 0};  // = (-5, 0, 0) in the volume's own frame
  vtkNew<vtkMatrix4x4> sliceToRAS;
  vtkRPSliceNode::ComputeSliceToRAS("Axial", center, sliceToRAS);
  rp::ResliceOptions options;
  options.FieldOfView[0] = options.FieldOfView[1] = 2;
  options.Spacing = 1;  // 2x2 pixels around the centre
  auto slice = rp::ResliceVolume(volume, sliceToRAS, options);
  // Pixel (0, 0) is half a pixel screen-left and down of the centre: +R (the screen's right is
  // the patient's left) and −A.
  const double local[3] = {-5 + 0.5, 0 - 0.5, 0};
  EXPECT_NEAR(slice->GetScalarComponentAsDouble(0, 0, 0, 0), Field(local), 1e-3);
}

TEST(NavigationLogic, SignedDistanceToASphereAndWarning) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(20);
  sphere->SetThetaResolution(128);
  sphere->SetPhiResolution(128);
  sphere->Update();
  vtkNew<vtkRPModelNode> bone;
  bone->SetPolyData(sphere->GetOutput());
  scene->AddNode(bone);
  vtkNew<vtkRPLinearTransformNode> tip;
  scene->AddNode(tip);
  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  logic->SetToolNodeID(tip->GetID());
  logic->SetTargetModelNodeIDs({bone->GetID()});
  logic->SetWarningDistance(3.0);
  // The tessellation of a 128×128 sphere of radius 20 lies within 20·(1−cos(π/128)) ≈ 0.006 mm.
  const double tolerance = 0.01;
  for (double r : {35.0, 22.5, 20.0, 10.0}) {
    const double m[16] = {1, 0, 0, r * 0.6, 0, 1, 0, r * 0.8, 0, 0, 1, 0, 0, 0, 0, 1};
    tip->SetMatrixTransformToParent(m);  // moving the tool updates the logic by itself
    const auto& result = logic->GetLastResult();
    ASSERT_TRUE(result.Valid);
    EXPECT_NEAR(result.DistanceMM, r - 20.0, tolerance) << "tip at radius " << r;
    EXPECT_EQ(result.Warning, r - 20.0 < 3.0);
    EXPECT_EQ(tip->GetAttribute("Navigation.Warning"), result.Warning ? "1" : "0");
    EXPECT_EQ(tip->GetAttribute("Navigation.ClosestModel"), bone->GetID());
  }
  // The closest point lies on the sphere, on the ray to the tip.
  const auto& last = logic->GetLastResult();
  const double norm = std::sqrt(last.ClosestPointRAS[0] * last.ClosestPointRAS[0] +
                                last.ClosestPointRAS[1] * last.ClosestPointRAS[1] +
                                last.ClosestPointRAS[2] * last.ClosestPointRAS[2]);
  EXPECT_NEAR(norm, 20.0, tolerance);
  // Removing the model: no result, no crash.
  scene->RemoveNode(bone);
  EXPECT_FALSE(logic->Update().Valid);
}
