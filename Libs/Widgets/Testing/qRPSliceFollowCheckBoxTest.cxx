// The "slices follow" check box: it drives the scene's slice nodes only, applies when its node
// appears, gives way when something else takes the slices, and stops only its own following.
#include <gtest/gtest.h>

#include <QApplication>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "qRPSliceFollowCheckBox.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"

TEST(SliceFollowCheckBox, DrivesTheSliceNodesOnly) {
  int argc = 1;
  char name[] = "qRPSliceFollowCheckBoxTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  qRPSliceFollowCheckBox box("Slices follow the tool");
  box.SetScene(scene);
  box.SetFollowNodeID("vtkRPLinearTransformNode1");  // not there yet
  box.setChecked(true);
  EXPECT_TRUE(vtkRPSliceNode::GetSliceNodes(scene).empty());  // nothing to follow: nothing changed
  vtkNew<vtkRPLinearTransformNode> tool;
  scene->AddNode(tool);
  ASSERT_EQ(tool->GetID(), "vtkRPLinearTransformNode1");
  box.Refresh();
  EXPECT_TRUE(box.IsFollowing());
  ASSERT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);  // the default views' nodes were added
  vtkNew<vtkMatrix4x4> pose;
  pose->SetElement(2, 3, 42);
  tool->SetMatrixTransformToParent(pose);
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetSliceOffset(), 42);

  // Another tool takes the slices: the box unticks and leaves them with it.
  vtkNew<vtkRPLinearTransformNode> other;
  scene->AddNode(other);
  vtkRPSliceNode::SetAllSlicesFollow(scene, other->GetID());
  box.Refresh();
  EXPECT_FALSE(box.isChecked());
  EXPECT_EQ(vtkRPSliceNode::GetSliceNode(scene, "Green")->GetFollowNodeID(), other->GetID());
  // Ticking takes them back; a new tool chosen while ticked takes them over.
  box.setChecked(true);
  EXPECT_TRUE(box.IsFollowing());
  box.SetFollowNodeID(other->GetID());
  EXPECT_TRUE(box.IsFollowing());
  EXPECT_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetFollowNodeID(), other->GetID());
  // Unticking stops following.
  box.setChecked(false);
  EXPECT_EQ(vtkRPSliceNode::GetSliceNode(scene, "Red")->GetFollowNodeID(), "");
  // The followed node leaves the scene: the box unticks.
  box.setChecked(true);
  scene->RemoveNode(other);
  box.Refresh();
  EXPECT_FALSE(box.isChecked());
}
