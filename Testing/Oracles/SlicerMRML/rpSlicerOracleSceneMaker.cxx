// rpSlicerOracleSceneMaker <out.rpscene>: a RoboPlan scene with one node of every class RoboPlan
// writes to .mrml, with known values, saved by rp::SaveScene, for the RoboPlan -> Slicer test
// (slicer_oracle_test.py roboplan-to-slicer). A CT volume with analytic voxels on an oblique grid
// (window/level), a segmentation on its grid with two segments (names, colours, tissue classes),
// a haptic bone model (colour, opacity, tissue class) and a hidden model, a transform under a
// transform, a tracked tool under it, fiducials under the inner transform, the three slice views
// and the layout, and node attributes. Test-only.
#include <iostream>
#include <string>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>

#include "rpSceneIO.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"

namespace {

template <class T>
T* Add(vtkRPScene* scene, const std::string& name) {
  vtkNew<T> node;
  node->SetName(name);
  scene->AddNode(node);
  return node;
}

void ObliqueGrid(vtkMatrix4x4* ijkToRas) {
  vtkNew<vtkTransform> t;
  t->Translate(-30.5, 12.25, -40.0);
  t->RotateWXYZ(25.0, 0.2, 0.3, 0.9);
  t->Scale(0.75, 0.8, 1.5);
  ijkToRas->DeepCopy(t->GetMatrix());
}

vtkRPScalarVolumeNode* AddVolumes(vtkRPScene* scene) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(20, 18, 12);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* ct = static_cast<short*>(image->GetScalarPointer());
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(20, 18, 12);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* label = static_cast<unsigned char*>(labels->GetScalarPointer());
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 18; ++j)
      for (int i = 0; i < 20; ++i) {
        *ct++ = static_cast<short>(-1000 + 7 * i + 40 * j + 150 * k);
        *label++ = k < 3 ? 1 : (i >= 8 && i < 12 && j >= 6 && j < 10 && k >= 5 && k < 9 ? 2 : 0);
      }
  vtkNew<vtkMatrix4x4> ijkToRas;
  ObliqueGrid(ijkToRas);
  auto* volume = Add<vtkRPScalarVolumeNode>(scene, "CT");
  volume->SetImageData(image);
  volume->SetIJKToRASMatrix(ijkToRas);
  volume->SetWindowLevel(1800.0, 350.0);
  volume->SetAttribute("Oracle.Content", "analytic CT");
  auto* seg = Add<vtkRPSegmentationNode>(scene, "Segmentation");
  seg->SetImageData(labels);
  seg->SetIJKToRASMatrix(ijkToRas);
  seg->SetSegment({"bone", "Bone", 1, {0.95, 0.84, 0.57}, "bone", {}});
  seg->SetSegment({"tumour", "Tumour", 2, {0.8, 0.1, 0.15}, "muscle", {}});
  return volume;
}

vtkRPLinearTransformNode* AddTransform(vtkRPScene* scene, const std::string& name, double angle, double ax, double ay,
                                       double az, double tx, double ty, double tz, vtkRPNode* parent) {
  vtkNew<vtkTransform> t;
  t->Translate(tx, ty, tz);
  t->RotateWXYZ(angle, ax, ay, az);
  auto* node = Add<vtkRPLinearTransformNode>(scene, name);
  node->SetMatrixTransformToParent(t->GetMatrix());
  if (parent) node->SetAndObserveTransformNodeID(parent->GetID());
  return node;
}

void AddModels(vtkRPScene* scene, vtkRPNode* parent) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(12.5, -7.0, 30.0);
  sphere->SetRadius(20.0);
  sphere->SetThetaResolution(18);
  sphere->SetPhiResolution(10);
  sphere->Update();
  auto* bone = Add<vtkRPModelNode>(scene, "Femur (haptic)");
  bone->SetPolyData(sphere->GetOutput());
  bone->SetColor(0.95, 0.84, 0.57);
  bone->SetOpacity(0.6);
  bone->SetHaptic(true);
  bone->SetTissueClass("bone");
  bone->SetAttribute("Oracle.Role", "haptic bone");
  auto* hidden = Add<vtkRPModelNode>(scene, "Skin");
  hidden->SetPolyData(sphere->GetOutput());
  hidden->SetColor(0.9, 0.7, 0.6);
  hidden->SetVisibility(false);
  hidden->SetTissueClass("skin");
  hidden->SetAndObserveTransformNodeID(parent->GetID());
}

void AddFiducialsAndTool(vtkRPScene* scene, vtkRPNode* inner) {
  auto* fiducials = Add<vtkRPFiducialListNode>(scene, "Landmarks");
  const double a[3] = {10.0, -20.5, 3.25}, b[3] = {-14.0, 8.0, 40.0}, c[3] = {0.5, 0.25, -60.0};
  fiducials->AddControlPoint(a, "medial");
  fiducials->AddControlPoint(b, "lateral");
  fiducials->AddControlPoint(c, "tip");
  fiducials->SetAndObserveTransformNodeID(inner->GetID());
  auto* tool = Add<vtkRPTrackedToolNode>(scene, "StylusToTracker");
  vtkNew<vtkTransform> t;
  t->Translate(3.0, -150.0, 22.0);
  t->RotateWXYZ(60.0, 1.0, 0.0, 1.0);
  tool->SetMatrixTransformToParent(t->GetMatrix());
  tool->SetAndObserveTransformNodeID(inner->GetID());
}

void AddViews(vtkRPScene* scene, vtkRPScalarVolumeNode* volume) {
  const char* views[3] = {"Red", "Yellow", "Green"};
  for (const char* view : views) {
    vtkNew<vtkRPSliceNode> slice;
    slice->SetName(view);
    slice->SetLayoutName(view);
    slice->SetOrientation(vtkRPSliceNode::GetDefaultOrientationForLayoutName(view));
    slice->SetBackgroundVolumeID(volume->GetID());
    scene->AddNode(slice);
  }
  vtkRPLayoutNode* layout = vtkRPLayoutNode::GetOrAddLayoutNode(scene);
  layout->SetViewArrangement(vtkRPLayoutNode::FourUp);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: rpSlicerOracleSceneMaker <out.rpscene>\n";
    return 2;
  }
  vtkNew<vtkRPScene> scene;
  vtkRPScalarVolumeNode* volume = AddVolumes(scene);
  vtkRPLinearTransformNode* outer = AddTransform(scene, "Outer", 20.0, 1, 0, 0, 5.0, -3.0, 12.0, nullptr);
  vtkRPLinearTransformNode* inner = AddTransform(scene, "Inner", 35.0, 0, 0.6, 0.8, -7.0, 2.0, 4.5, outer);
  AddModels(scene, outer);
  AddFiducialsAndTool(scene, inner);
  AddViews(scene, volume);
  std::string error;
  if (!rp::SaveScene(scene, argv[1], error)) {
    std::cerr << "rpSlicerOracleSceneMaker: " << error << "\n";
    return 1;
  }
  std::cout << "wrote " << argv[1] << " (" << scene->GetNumberOfNodes() << " nodes)\n";
  return 0;
}
