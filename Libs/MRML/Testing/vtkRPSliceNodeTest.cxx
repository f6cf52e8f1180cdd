// Slice nodes: the one definition of the standard slice frames (against Slicer's values and the
// radiological convention), the plane operations, following a tool, singletons in the scene.
#include <gtest/gtest.h>

#include <cmath>

#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "vtkRPLayoutNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"

namespace {

// Slice coordinates (right, up, along the normal) of a RAS point.
void RASToSlice(const vtkMatrix4x4* sliceToRAS, const double ras[3], double slice[3]) {
  vtkNew<vtkMatrix4x4> rasToSlice;
  vtkMatrix4x4::Invert(sliceToRAS, rasToSlice);
  const double in[4] = {ras[0], ras[1], ras[2], 1.0};
  double out[4];
  rasToSlice->MultiplyPoint(in, out);
  for (int i = 0; i < 3; ++i) slice[i] = out[i];
}

}  // namespace

// Element for element what Slicer's vtkMRMLSliceNode::InitializeAxialMatrix,
// InitializeSagittalMatrix and InitializeCoronalMatrix set (Libs/MRML/Core/vtkMRMLSliceNode.cxx).
TEST(SliceNode, StandardFramesAreSlicers) {
  const double axial[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double sagittal[3][3] = {{0, 0, 1}, {-1, 0, 0}, {0, 1, 0}};
  const double coronal[3][3] = {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}};
  const std::pair<const char*, const double(*)[3]> expected[] = {{"Axial", axial}, {"Sagittal", sagittal}, {"Coronal", coronal}};
  for (const auto& [name, matrix] : expected) {
    double m[3][3];
    ASSERT_TRUE(vtkRPSliceNode::GetOrientationMatrix(name, m)) << name;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(m[r][c], matrix[r][c]) << name << " (" << r << "," << c << ")";
  }
  double m[3][3];
  EXPECT_FALSE(vtkRPSliceNode::GetOrientationMatrix("Oblique", m));
  EXPECT_EQ(vtkRPSliceNode::GetDefaultOrientationForLayoutName("Red"), "Axial");
  EXPECT_EQ(vtkRPSliceNode::GetDefaultOrientationForLayoutName("Yellow"), "Sagittal");
  EXPECT_EQ(vtkRPSliceNode::GetDefaultOrientationForLayoutName("Green"), "Coronal");
}

// The known answer a radiologist checks first: in axial and coronal views the patient's left is
// on the screen's right; anterior is up in axial and on the left in sagittal; superior is up in
// sagittal and coronal; the slice offset grows along S, R and A.
TEST(SliceNode, RadiologicalScreenDirections) {
  const double centre[3] = {10, -20, 30};
  const double left[3] = {centre[0] - 50, centre[1], centre[2]};       // patient's left of the centre
  const double anterior[3] = {centre[0], centre[1] + 50, centre[2]};
  const double superior[3] = {centre[0], centre[1], centre[2] + 50};
  vtkNew<vtkMatrix4x4> m;
  double s[3];

  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Axial", centre, m));
  RASToSlice(m, left, s);
  EXPECT_NEAR(s[0], 50, 1e-12);  // left → right of the screen
  RASToSlice(m, anterior, s);
  EXPECT_NEAR(s[1], 50, 1e-12);  // anterior → up
  RASToSlice(m, superior, s);
  EXPECT_NEAR(s[2], 50, 1e-12);  // normal along S

  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Sagittal", centre, m));
  RASToSlice(m, anterior, s);
  EXPECT_NEAR(s[0], -50, 1e-12);  // anterior → left of the screen
  RASToSlice(m, superior, s);
  EXPECT_NEAR(s[1], 50, 1e-12);
  RASToSlice(m, left, s);
  EXPECT_NEAR(s[2], -50, 1e-12);  // normal along R

  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Coronal", centre, m));
  RASToSlice(m, left, s);
  EXPECT_NEAR(s[0], 50, 1e-12);
  RASToSlice(m, superior, s);
  EXPECT_NEAR(s[1], 50, 1e-12);
  RASToSlice(m, anterior, s);
  EXPECT_NEAR(s[2], 50, 1e-12);  // normal along A
}

TEST(SliceNode, ToolPlaneContainsTheShaft) {
  // Tool rotated 90° about R: tool z (shaft) along −A, tool x along R; tip at (1, 2, 3).
  vtkNew<vtkMatrix4x4> tool, slice;
  tool->SetElement(1, 1, 0);
  tool->SetElement(1, 2, 1);
  tool->SetElement(2, 1, -1);
  tool->SetElement(2, 2, 0);
  tool->SetElement(0, 3, 1);
  tool->SetElement(1, 3, 2);
  tool->SetElement(2, 3, 3);
  vtkRPSliceNode::ComputeSliceToRASForTool(tool, slice);
  for (int r = 0; r < 3; ++r) {
    EXPECT_DOUBLE_EQ(slice->GetElement(r, 0), tool->GetElement(r, 0));
    EXPECT_DOUBLE_EQ(slice->GetElement(r, 1), tool->GetElement(r, 2));
    EXPECT_DOUBLE_EQ(slice->GetElement(r, 2), -tool->GetElement(r, 1));
    EXPECT_DOUBLE_EQ(slice->GetElement(r, 3), tool->GetElement(r, 3));
  }
}

TEST(SliceNode, PlaneOperations) {
  vtkNew<vtkRPSliceNode> node;
  EXPECT_EQ(node->GetOrientation(), "Axial");
  const double p[3] = {5, 6, 7};
  node->JumpSlice(p);
  EXPECT_DOUBLE_EQ(node->GetSliceOffset(), 7);
  double origin[3];
  node->GetOrigin(origin);
  EXPECT_DOUBLE_EQ(origin[0], 0);  // offset jump: the plane moves along its normal only
  EXPECT_DOUBLE_EQ(origin[1], 0);
  const double nan[3] = {std::nan(""), 0, 0};
  node->JumpSlice(nan);
  EXPECT_DOUBLE_EQ(node->GetSliceOffset(), 7);

  ASSERT_TRUE(node->SetOrientation("Sagittal"));
  EXPECT_EQ(node->GetOrientation(), "Sagittal");
  EXPECT_DOUBLE_EQ(node->GetSliceOffset(), 0);  // the plane through the same origin
  EXPECT_FALSE(node->SetOrientation("Diagonal"));
  EXPECT_EQ(node->GetOrientation(), "Sagittal");

  // A rotated plane is a reformat; a scaled, skewed matrix is made orthonormal.
  vtkNew<vtkMatrix4x4> oblique;
  oblique->SetElement(0, 0, 2);
  oblique->SetElement(1, 0, 2);
  oblique->SetElement(0, 1, -1);
  oblique->SetElement(1, 1, 1.5);
  oblique->SetElement(2, 2, 3);
  ASSERT_TRUE(node->SetSliceToRAS(oblique));
  EXPECT_EQ(node->GetOrientation(), "Reformat");
  const vtkMatrix4x4* m = node->GetSliceToRAS();
  double x[3], y[3], n[3];
  for (int r = 0; r < 3; ++r) x[r] = m->GetElement(r, 0), y[r] = m->GetElement(r, 1), n[r] = m->GetElement(r, 2);
  EXPECT_NEAR(vtkMath::Norm(x), 1, 1e-12);
  EXPECT_NEAR(vtkMath::Norm(y), 1, 1e-12);
  EXPECT_NEAR(vtkMath::Dot(x, y), 0, 1e-12);
  EXPECT_NEAR(n[2], 1, 1e-12);
  // The coronal preset given as a matrix is recognised.
  vtkNew<vtkMatrix4x4> coronal;
  ASSERT_TRUE(vtkRPSliceNode::ComputeSliceToRAS("Coronal", p, coronal));
  ASSERT_TRUE(node->SetSliceToRAS(coronal));
  EXPECT_EQ(node->GetOrientation(), "Coronal");
  EXPECT_DOUBLE_EQ(node->GetSliceOffset(), 6);
  // Degenerate planes are refused and change nothing.
  vtkNew<vtkMatrix4x4> flat;
  flat->SetElement(1, 1, 0);  // up = 0
  EXPECT_FALSE(node->SetSliceToRAS(flat));
  EXPECT_EQ(node->GetOrientation(), "Coronal");

  node->SetFieldOfView(-1, 100);
  EXPECT_DOUBLE_EQ(node->GetFieldOfView()[0], 250);
  node->SetForegroundOpacity(2);
  EXPECT_DOUBLE_EQ(node->GetForegroundOpacity(), 1);
}

TEST(SliceNode, FollowsTheTipOfATransformChain) {
  vtkNew<vtkRPScene> scene;
  const auto nodes = vtkRPSliceNode::GetOrAddDefaultSliceNodes(scene);
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_EQ(nodes[0]->GetLayoutName(), "Red");
  EXPECT_EQ(nodes[1]->GetOrientation(), "Sagittal");
  EXPECT_EQ(nodes[2]->GetID(), "vtkRPSliceNodeGreen");
  EXPECT_EQ(vtkRPSliceNode::GetOrAddDefaultSliceNodes(scene).size(), 3u);
  EXPECT_EQ(scene->GetNumberOfNodes(), 3);  // not added twice

  vtkNew<vtkRPLinearTransformNode> parent, tip;
  scene->AddNode(parent);
  scene->AddNode(tip);
  tip->SetAndObserveTransformNodeID(parent->GetID());
  vtkNew<vtkMatrix4x4> m;
  m->SetElement(0, 3, 1);
  m->SetElement(1, 3, 2);
  m->SetElement(2, 3, 3);
  tip->SetMatrixTransformToParent(m);
  EXPECT_FALSE(vtkRPSliceNode::SetAllSlicesFollow(scene, "noSuchNode"));
  ASSERT_TRUE(vtkRPSliceNode::SetAllSlicesFollow(scene, tip->GetID()));
  EXPECT_DOUBLE_EQ(nodes[0]->GetSliceOffset(), 3);   // S
  EXPECT_DOUBLE_EQ(nodes[1]->GetSliceOffset(), 1);   // R
  EXPECT_DOUBLE_EQ(nodes[2]->GetSliceOffset(), 2);   // A
  // Moving a parent moves the slices.
  vtkNew<vtkMatrix4x4> shift;
  shift->SetElement(2, 3, 100);
  parent->SetMatrixTransformToParent(shift);
  EXPECT_DOUBLE_EQ(nodes[0]->GetSliceOffset(), 103);
  // The followed node leaves the scene: the slices stay where they are and stop following.
  scene->RemoveNode(tip);
  EXPECT_EQ(nodes[0]->GetFollowNodeID(), "");
  parent->SetMatrixTransformToParent(m);
  EXPECT_DOUBLE_EQ(nodes[0]->GetSliceOffset(), 103);
  // A model node is transformable (it can be followed); the scene node is not a transform.
  vtkNew<vtkRPScalarVolumeNode> volume;
  scene->AddNode(volume);
  EXPECT_TRUE(nodes[0]->SetAndObserveFollowNodeID(volume->GetID()));
  EXPECT_FALSE(nodes[0]->SetAndObserveFollowNodeID(nodes[1]->GetID()));
}

TEST(SliceNode, SingletonsAreUpdatedNotDuplicatedAndSurviveClose) {
  vtkNew<vtkRPScene> scene;
  const auto nodes = vtkRPSliceNode::GetOrAddDefaultSliceNodes(scene);
  vtkNew<vtkRPScalarVolumeNode> ct;
  scene->AddNode(ct);
  nodes[0]->SetBackgroundVolumeID(ct->GetID());

  // Adding another "Red" node updates the scene's.
  vtkNew<vtkRPSliceNode> another;
  another->SetLayoutName("Red");
  another->SetOrientationToCoronal();
  EXPECT_EQ(scene->AddNode(another), nodes[0]);
  EXPECT_EQ(nodes[0]->GetOrientation(), "Coronal");
  EXPECT_EQ(another->GetScene(), nullptr);
  EXPECT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);
  nodes[0]->SetOrientationToAxial();

  // Importing a saved view (with a volume it refers to, whose ID clashes): merged and remapped.
  auto importedVolume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  importedVolume->SetIDInternal(ct->GetID());
  importedVolume->SetName("MR");
  auto importedRed = vtkSmartPointer<vtkRPSliceNode>::New();
  importedRed->SetIDInternal("vtkRPSliceNodeRed");
  importedRed->SetLayoutName("Red");
  importedRed->SetName("Red");
  const double p[3] = {0, 0, 42};
  importedRed->JumpSlice(p);
  importedRed->SetFieldOfView(120, 90);
  importedRed->AddNodeReferenceID(vtkRPSliceNode::BackgroundVolumeRole(), ct->GetID());
  auto layout = vtkSmartPointer<vtkRPLayoutNode>::New();
  layout->SetViewArrangement(vtkRPLayoutNode::OneUp3D);
  const auto remap = scene->Import({importedVolume, importedRed, layout});
  EXPECT_EQ(remap.at("vtkRPSliceNodeRed"), "vtkRPSliceNodeRed");
  EXPECT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);
  EXPECT_DOUBLE_EQ(nodes[0]->GetSliceOffset(), 42);
  EXPECT_DOUBLE_EQ(nodes[0]->GetFieldOfView()[1], 90);
  EXPECT_NE(importedVolume->GetID(), ct->GetID());
  EXPECT_EQ(nodes[0]->GetBackgroundVolumeID(), importedVolume->GetID());  // the imported MR, not the CT
  EXPECT_EQ(vtkRPLayoutNode::GetOrAddLayoutNode(scene), layout.GetPointer());  // none before: added
  EXPECT_EQ(vtkRPLayoutNode::GetOrAddLayoutNode(scene)->GetViewArrangement(), vtkRPLayoutNode::OneUp3D);

  // Closing keeps the views' nodes (without their references to the removed data).
  scene->Clear();
  EXPECT_EQ(scene->GetNumberOfNodes(), 4);
  EXPECT_EQ(nodes[0]->GetBackgroundVolumeID(), "");
  EXPECT_EQ(nodes[0]->GetScene(), scene.GetPointer());
}

TEST(SliceNode, PropertiesRoundTrip) {
  vtkNew<vtkRPSliceNode> node;
  node->SetLayoutName("Yellow");
  node->SetOrientationToSagittal();
  const double p[3] = {12.5, -3, 4};
  node->JumpSlice(p);
  node->SetFieldOfView(180, 140);
  node->SetXYOrigin(3, -4);
  node->SetSliceVisible(false);
  node->SetForegroundOpacity(0.25);
  node->SetLabelOpacity(0.75);
  vtkRPNode::PropertyMap properties;
  node->WriteProperties(properties);
  vtkNew<vtkRPSliceNode> read;
  read->ReadProperties(properties);
  EXPECT_EQ(read->GetLayoutName(), "Yellow");
  EXPECT_EQ(read->GetSingletonTag(), "Yellow");
  EXPECT_EQ(read->GetOrientation(), "Sagittal");
  EXPECT_DOUBLE_EQ(read->GetSliceOffset(), 12.5);
  EXPECT_DOUBLE_EQ(read->GetFieldOfView()[0], 180);
  EXPECT_DOUBLE_EQ(read->GetXYOrigin()[1], -4);
  EXPECT_FALSE(read->GetSliceVisible());
  EXPECT_DOUBLE_EQ(read->GetForegroundOpacity(), 0.25);
  EXPECT_DOUBLE_EQ(read->GetLabelOpacity(), 0.75);
  // A matrix that is not a plane is not taken.
  properties["sliceToRAS"] = "0 0 0 0  0 0 0 0  0 0 0 0  0 0 0 1";
  vtkNew<vtkRPSliceNode> broken;
  broken->ReadProperties(properties);
  EXPECT_EQ(broken->GetOrientation(), "Axial");
}
