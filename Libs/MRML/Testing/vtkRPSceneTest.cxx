// Scene, node, reference and transform-chain behaviour with hand-computed answers.
#include <gtest/gtest.h>

#include <limits>

#include <vtkCallbackCommand.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"

namespace {
// Counts events of one id on one object.
struct EventCounter {
  int Count = 0;
  vtkNew<vtkCallbackCommand> Callback;
  EventCounter(vtkObject* object, unsigned long event) {
    this->Callback->SetClientData(this);
    this->Callback->SetCallback([](vtkObject*, unsigned long, void* self, void*) { ++static_cast<EventCounter*>(self)->Count; });
    object->AddObserver(event, this->Callback);
  }
};

vtkSmartPointer<vtkMatrix4x4> Matrix(std::initializer_list<double> rowMajor) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  int i = 0;
  for (double v : rowMajor) m->SetElement(i / 4, i % 4, v), ++i;
  return m;
}
}  // namespace

TEST(Scene, AddFindRemoveWithUniqueIDsAndNames) {
  vtkNew<vtkRPScene> scene;
  EventCounter added(scene, vtkRPScene::NodeAddedEvent);
  EventCounter aboutToRemove(scene, vtkRPScene::NodeAboutToBeRemovedEvent);
  EventCounter removed(scene, vtkRPScene::NodeRemovedEvent);
  vtkNew<vtkRPModelNode> a, b;
  a->SetName("Femur");
  b->SetName("Femur");
  scene->AddNode(a);
  scene->AddNode(b);
  vtkNew<vtkRPLinearTransformNode> t;
  scene->AddNode(t);
  EXPECT_EQ(added.Count, 3);
  EXPECT_NE(a->GetID(), b->GetID());
  EXPECT_EQ(a->GetName(), "Femur");
  EXPECT_EQ(b->GetName(), "Femur_1");  // names made unique
  EXPECT_EQ(t->GetName(), "LinearTransform");
  EXPECT_EQ(scene->GetNodeByID(a->GetID()), a.GetPointer());
  EXPECT_EQ(scene->GetNodesByName("Femur").size(), 1u);
  EXPECT_EQ(scene->GetNodesByClass("vtkRPModelNode").size(), 2u);
  EXPECT_EQ(scene->GetNodesByClass("vtkRPTransformableNode").size(), 3u);  // IsA includes subclasses
  EXPECT_EQ(scene->AddNode(a), nullptr);  // already in a scene
  scene->RemoveNode(a);
  EXPECT_EQ(aboutToRemove.Count, 1);
  EXPECT_EQ(removed.Count, 1);
  EXPECT_EQ(scene->GetNodeByID(a->GetID()), nullptr);
  EXPECT_EQ(a->GetScene(), nullptr);
  EventCounter startClose(scene, vtkRPScene::StartCloseEvent), endClose(scene, vtkRPScene::EndCloseEvent);
  scene->Clear();
  EXPECT_EQ(scene->GetNumberOfNodes(), 0);
  EXPECT_EQ(startClose.Count, 1);
  EXPECT_EQ(endClose.Count, 1);
}

TEST(Node, BatchModifyCollapsesToOneEvent) {
  vtkNew<vtkRPModelNode> model;
  EventCounter modified(model, vtkCommand::ModifiedEvent);
  model->SetName("Tibia");
  EXPECT_EQ(modified.Count, 1);
  const int previous = model->StartModify();
  model->SetColor(1, 0, 0);
  model->SetOpacity(0.5);
  model->SetTissueClass("bone");
  model->SetAttribute("Haptic.Stiffness", "0.8");
  const int nested = model->StartModify();  // nested batches fire once at the outermost end
  model->SetVisibility(false);
  model->EndModify(nested);
  EXPECT_EQ(modified.Count, 1);
  model->EndModify(previous);
  EXPECT_EQ(modified.Count, 2);
  model->EndModify(model->StartModify());  // empty batch: no event
  EXPECT_EQ(modified.Count, 2);
  model->SetOpacity(0.5);  // no change: no event
  EXPECT_EQ(modified.Count, 2);
}

TEST(Node, AttributesAndReferencesClearedOnRemoval) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPFiducialListNode> from, to;
  vtkNew<vtkRPLinearTransformNode> result;
  scene->AddNode(from);
  scene->AddNode(to);
  scene->AddNode(result);
  result->SetNodeReferenceID("fromFiducials", from->GetID());
  result->SetNodeReferenceID("toFiducials", to->GetID());
  result->AddNodeReferenceID("inputs", from->GetID());
  result->AddNodeReferenceID("inputs", to->GetID());
  EXPECT_EQ(result->GetNodeReference("fromFiducials"), from.GetPointer());
  EXPECT_EQ(result->GetNumberOfNodeReferences("inputs"), 2);
  EventCounter referenceModified(result, vtkRPNode::ReferenceModifiedEvent);
  scene->RemoveNode(from);
  EXPECT_EQ(result->GetNodeReferenceID("fromFiducials"), "");
  EXPECT_EQ(result->GetNumberOfNodeReferences("inputs"), 1);
  EXPECT_EQ(result->GetNodeReference("inputs"), to.GetPointer());
  EXPECT_EQ(referenceModified.Count, 2);  // one event per role that changed (two roles)
  result->SetAttribute("Registration.FRE", "0.31");
  EXPECT_EQ(result->GetAttribute("Registration.FRE"), "0.31");
  EXPECT_EQ(result->GetAttribute("missing"), "");
}

TEST(Scene, ImportRemapsClashingIDsAndReferences) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> existing;
  scene->AddNode(existing);  // takes vtkRPLinearTransformNode1
  ASSERT_EQ(existing->GetID(), "vtkRPLinearTransformNode1");

  // Nodes from a file: their IDs clash with the scene's; a model references the transform.
  auto transform = vtkSmartPointer<vtkRPLinearTransformNode>::New();
  transform->SetIDInternal("vtkRPLinearTransformNode1");
  transform->SetName("TrackerToRAS");
  auto model = vtkSmartPointer<vtkRPModelNode>::New();
  model->SetIDInternal("vtkRPModelNode1");
  model->SetNodeReferenceID(vtkRPTransformableNode::TransformRole(), "vtkRPLinearTransformNode1");
  EventCounter startImport(scene, vtkRPScene::StartImportEvent), endImport(scene, vtkRPScene::EndImportEvent);
  const auto remap = scene->Import({transform, model});
  EXPECT_EQ(startImport.Count, 1);
  EXPECT_EQ(endImport.Count, 1);
  EXPECT_NE(transform->GetID(), "vtkRPLinearTransformNode1");
  EXPECT_EQ(remap.at("vtkRPLinearTransformNode1"), transform->GetID());
  EXPECT_EQ(model->GetTransformNodeID(), transform->GetID());  // followed the remap
  EXPECT_EQ(model->GetParentTransformNode(), transform.GetPointer());
  EXPECT_EQ(existing->GetScene(), scene.GetPointer());  // existing node untouched
}

TEST(Transforms, ChainMathAgainstHandComputedMatrices) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;
  vtkNew<vtkRPTrackedToolNode> stylusToTracker;
  vtkNew<vtkRPLinearTransformNode> tipToStylus;
  vtkNew<vtkRPModelNode> needle;
  scene->AddNode(trackerToRAS);
  scene->AddNode(stylusToTracker);
  scene->AddNode(tipToStylus);
  scene->AddNode(needle);
  // 90° about S plus a shift; a pure translation; a tip offset along the stylus.
  trackerToRAS->SetMatrixTransformToParent(Matrix({0, -1, 0, 10, 1, 0, 0, 20, 0, 0, 1, 30, 0, 0, 0, 1}));
  stylusToTracker->SetMatrixTransformToParent(Matrix({1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  tipToStylus->SetMatrixTransformToParent(Matrix({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 100, 0, 0, 0, 1}));
  ASSERT_TRUE(stylusToTracker->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  ASSERT_TRUE(tipToStylus->SetAndObserveTransformNodeID(stylusToTracker->GetID()));
  ASSERT_TRUE(needle->SetAndObserveTransformNodeID(tipToStylus->GetID()));

  vtkNew<vtkMatrix4x4> toWorld;
  needle->GetMatrixTransformToWorld(toWorld);
  // Tip origin: (0,0,0) → tip→stylus (0,0,100) → stylus→tracker (5,0,100) → tracker→RAS:
  // x' = -y + 10 = 10, y' = x + 20 = 25, z' = z + 30 = 130.
  double origin[4] = {0, 0, 0, 1}, out[4];
  toWorld->MultiplyPoint(origin, out);
  EXPECT_DOUBLE_EQ(out[0], 10);
  EXPECT_DOUBLE_EQ(out[1], 25);
  EXPECT_DOUBLE_EQ(out[2], 130);
  // A unit x in the needle frame maps to +y in RAS (90° about S).
  EXPECT_DOUBLE_EQ(toWorld->GetElement(1, 0), 1);
  EXPECT_DOUBLE_EQ(toWorld->GetElement(0, 0), 0);

  // Changing the top of the chain fires TransformModifiedEvent on everything below it.
  EventCounter needleMoved(needle, vtkRPNode::TransformModifiedEvent);
  EventCounter tipMoved(tipToStylus, vtkRPNode::TransformModifiedEvent);
  trackerToRAS->SetMatrixTransformToParent(Matrix({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  EXPECT_EQ(needleMoved.Count, 1);
  EXPECT_EQ(tipMoved.Count, 1);
  needle->GetMatrixTransformToWorld(toWorld);
  toWorld->MultiplyPoint(origin, out);
  EXPECT_DOUBLE_EQ(out[0], 5);
  EXPECT_DOUBLE_EQ(out[2], 100);

  // Cycles are refused and leave the hierarchy unchanged.
  EXPECT_FALSE(trackerToRAS->SetAndObserveTransformNodeID(tipToStylus->GetID()));
  EXPECT_FALSE(trackerToRAS->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  EXPECT_EQ(trackerToRAS->GetTransformNodeID(), "");
  // Only transform nodes can be parents.
  EXPECT_FALSE(needle->SetAndObserveTransformNodeID(scene->GetNthNode(3)->GetID()));

  // Removing a transform in the middle detaches its children (reference cleared).
  scene->RemoveNode(stylusToTracker);
  EXPECT_EQ(tipToStylus->GetParentTransformNode(), nullptr);
  EXPECT_EQ(needleMoved.Count, 2);  // the chain above the needle changed
}

TEST(Fiducials, PointEventsAndWorldPositions) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPFiducialListNode> list;
  list->SetName("F");
  scene->AddNode(list);
  EventCounter pointModified(list, vtkRPFiducialListNode::PointModifiedEvent);
  const double p[3] = {1, 2, 3};
  EXPECT_EQ(list->AddControlPoint(p), 0);
  EXPECT_EQ(list->GetNthControlPoint(0).Label, "F-1");
  const double q[3] = {4, 5, 6};
  EXPECT_TRUE(list->SetNthControlPointPosition(0, q));
  EXPECT_EQ(pointModified.Count, 1);
  list->SetNthControlPointLocked(0, true);
  EXPECT_FALSE(list->SetNthControlPointPosition(0, p));  // locked points do not move
  vtkNew<vtkRPLinearTransformNode> shift;
  scene->AddNode(shift);
  shift->SetMatrixTransformToParent(Matrix({1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  list->SetAndObserveTransformNodeID(shift->GetID());
  double world[3];
  list->GetNthControlPointPositionWorld(0, world);
  EXPECT_DOUBLE_EQ(world[0], 14);
  EXPECT_DOUBLE_EQ(world[1], 5);
}

TEST(Volume, GeometryFromSpacingOriginDirections) {
  vtkNew<vtkRPScalarVolumeNode> volume;
  const double spacing[3] = {0.5, 0.5, 2.0}, origin[3] = {-10, 20, 5};
  const double directions[3][3] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};  // LPS-aligned axes in RAS
  volume->SetGeometry(spacing, origin, directions);
  double s[3], o[3];
  volume->GetSpacing(s);
  volume->GetOrigin(o);
  EXPECT_DOUBLE_EQ(s[2], 2.0);
  EXPECT_DOUBLE_EQ(o[1], 20);
  EXPECT_DOUBLE_EQ(volume->GetIJKToRASMatrix()->GetElement(0, 0), -0.5);
}

TEST(Volume, WindowLevelSpansTheVoxelRange) {
  // Integer voxels (a fast min/max of our own) and float voxels (VTK's range, which skips NaN).
  vtkNew<vtkRPScalarVolumeNode> volume;
  vtkNew<vtkImageData> ct;
  ct->SetDimensions(300, 200, 50);  // 3 M voxels: several parallel chunks
  ct->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(ct->GetScalarPointer());
  for (vtkIdType i = 0; i < 300 * 200 * 50; ++i) v[i] = static_cast<short>(i % 1000);
  v[1234567] = -1024, v[2999999] = 3071;
  volume->SetImageData(ct);
  volume->SetWindowLevelFromScalarRange();
  EXPECT_DOUBLE_EQ(volume->GetWindow(), 4095);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), 1023.5);
  vtkNew<vtkImageData> labels;  // unsigned: the ends are not the type's
  labels->SetDimensions(5, 1, 1);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* l = static_cast<unsigned char*>(labels->GetScalarPointer());
  l[0] = 3, l[1] = 7, l[2] = 250, l[3] = 2, l[4] = 9;
  volume->SetImageData(labels);
  volume->SetWindowLevelFromScalarRange();
  EXPECT_DOUBLE_EQ(volume->GetWindow(), 248);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), 126);
  vtkNew<vtkImageData> dose;
  dose->SetDimensions(4, 1, 1);
  dose->AllocateScalars(VTK_FLOAT, 1);
  auto* f = static_cast<float*>(dose->GetScalarPointer());
  f[0] = 0.5f, f[1] = std::numeric_limits<float>::quiet_NaN(), f[2] = 2.5f, f[3] = 1.0f;
  volume->SetImageData(dose);
  volume->SetWindowLevelFromScalarRange();
  EXPECT_DOUBLE_EQ(volume->GetWindow(), 2.0);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), 1.5);
}
