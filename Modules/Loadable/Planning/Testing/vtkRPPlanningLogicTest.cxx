// Planning logic: structures at risk found on models and segments, their surfaces in world RAS,
// and the plan handed to real-time code as an immutable snapshot (rpPlanSnapshot.h).
#include <gtest/gtest.h>

#include <cmath>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>

#include "vtkRPCutPlaneNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

namespace {

vtkRPModelNode* AddSphereModel(vtkRPScene* scene, const char* name, double radius, bool isProtected, double margin) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(48);
  sphere->SetPhiResolution(24);
  sphere->Update();
  vtkNew<vtkRPModelNode> model;
  model->SetName(name);
  model->SetPolyData(sphere->GetOutput());
  model->SetProtection({isProtected, margin});
  return vtkRPModelNode::SafeDownCast(scene->AddNode(model));
}

// A 20^3 labelmap, 1 mm voxels at the origin: label 1 a box [5,14]^3.
vtkRPSegmentationNode* AddBoxSegment(vtkRPScene* scene, bool isProtected) {
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(20, 20, 20);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(labels->GetScalarPointer());
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) *v++ = (i >= 5 && i < 15 && j >= 5 && j < 15 && k >= 5 && k < 15) ? 1 : 0;
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName("Labels");
  segmentation->SetImageData(labels);
  rp::Segment s;
  s.ID = "nerve", s.Name = "Nerve", s.LabelValue = 1;
  s.Protection = {isProtected, 1.5};
  segmentation->SetSegment(s);
  return vtkRPSegmentationNode::SafeDownCast(scene->AddNode(segmentation));
}

}  // namespace

TEST(PlanningLogic, StructuresAtRiskAreTheProtectedModelsAndSegments) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPPlanningLogic> logic;
  logic->SetScene(scene);
  AddSphereModel(scene, "Vessels", 5, true, 3);
  AddSphereModel(scene, "Tibia", 20, false, 0);
  AddBoxSegment(scene, true);
  const auto structures = logic->GetStructuresAtRisk();
  ASSERT_EQ(structures.size(), 2u);
  EXPECT_EQ(structures[0].Name, "Vessels");
  EXPECT_EQ(structures[0].SafetyMarginMm, 3);
  EXPECT_EQ(structures[1].Name, "Nerve");
  EXPECT_EQ(structures[1].SegmentID, "nerve");
  EXPECT_EQ(structures[1].SafetyMarginMm, 1.5);
}

TEST(PlanningLogic, TheSnapshotHoldsThePlanInWorldCoordinatesWithClosedSurfaces) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPPlanningLogic> logic;
  logic->SetScene(scene);
  vtkRPModelNode* vessels = AddSphereModel(scene, "Vessels", 5, true, 3);
  vtkNew<vtkRPLinearTransformNode> shift;
  const double m[16] = {1, 0, 0, 100, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  shift->SetMatrixTransformToParent(m);
  scene->AddNode(shift);
  vessels->SetAndObserveTransformNodeID(shift->GetID());
  vtkRPSegmentationNode* labels = AddBoxSegment(scene, true);

  vtkNew<vtkRPScrewNode> screw;
  screw->SetName("Screw");
  const double entry[3] = {0, 0, 0}, target[3] = {0, 0, 40};
  screw->SetEntryAndTarget(entry, target);
  screw->SetScrewLengthMm(30);
  scene->AddNode(screw);
  screw->SetAndObserveTransformNodeID(shift->GetID());
  vtkNew<vtkRPTrajectoryNode> unfinished;  // one point only: not in the snapshot
  unfinished->AddControlPoint(entry);
  scene->AddNode(unfinished);
  vtkNew<vtkRPCutPlaneNode> plane;
  plane->SetOrigin(target);
  scene->AddNode(plane);

  std::string error;
  const auto plan = logic->MakePlanSnapshot(error);
  ASSERT_NE(plan, nullptr) << error;
  ASSERT_EQ(plan->Trajectories.size(), 1u);
  const rp::TrajectorySnapshot& t = plan->Trajectories[0];
  EXPECT_TRUE(t.IsScrew);
  EXPECT_EQ(t.ScrewLengthMm, 30);
  EXPECT_EQ(t.Entry.x, 100);  // under the transform
  EXPECT_EQ(t.Target.z, 40);
  EXPECT_EQ(plan->FindTrajectory("Screw"), &t);
  ASSERT_EQ(plan->Planes.size(), 1u);
  EXPECT_EQ(plan->Planes[0].Normal.z, 1);
  ASSERT_EQ(plan->StructuresAtRisk.size(), 2u);
  const rp::StructureAtRiskSnapshot& sphere = plan->StructuresAtRisk[0];
  ASSERT_NE(sphere.Signed, nullptr);  // a closed sphere: signed distance
  EXPECT_NEAR(sphere.Signed->SignedDistance({100, 0, 0}), -5, 0.05);
  EXPECT_NEAR(sphere.Signed->SignedDistance({110, 0, 0}), 5, 0.05);
  const rp::StructureAtRiskSnapshot& box = plan->StructuresAtRisk[1];
  EXPECT_EQ(box.SegmentID, "nerve");
  ASSERT_NE(box.Signed, nullptr);
  EXPECT_LT(box.Signed->SignedDistance({9.5, 9.5, 9.5}), -4);  // the box's centre, inside
  EXPECT_GT(box.Signed->SignedDistance({0, 0, 0}), 4);

  // The segment is meshed once; a changed segmentation is meshed again.
  std::string again;
  const auto first = logic->GetStructureSurface(logic->GetStructuresAtRisk()[1], again);
  EXPECT_EQ(logic->GetStructureSurface(logic->GetStructuresAtRisk()[1], again), first);
  labels->Modified();
  EXPECT_NE(logic->GetStructureSurface(logic->GetStructuresAtRisk()[1], again), first);
}

TEST(PlanningLogic, APlanThatCannotBeGuidedIsRefusedNamingWhy) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPPlanningLogic> logic;
  logic->SetScene(scene);
  vtkNew<vtkRPTrajectoryNode> tunnel;
  tunnel->SetName("Tunnel");
  const double p[3] = {1, 2, 3};
  tunnel->SetEntryAndTarget(p, p);
  scene->AddNode(tunnel);
  std::string error;
  EXPECT_EQ(logic->MakePlanSnapshot(error), nullptr);
  EXPECT_NE(error.find("'Tunnel' has zero length"), std::string::npos) << error;
  scene->RemoveNode(tunnel);

  vtkNew<vtkRPModelNode> empty;
  empty->SetName("Empty nerve");
  empty->SetProtection({true, 1});
  scene->AddNode(empty);
  EXPECT_EQ(logic->MakePlanSnapshot(error), nullptr);
  EXPECT_NE(error.find("'Empty nerve'"), std::string::npos) << error;
}
