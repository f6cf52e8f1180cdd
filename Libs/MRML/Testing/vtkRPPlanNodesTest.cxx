// Plan nodes as scene objects: a trajectory holds two points and changes in one event, a cut
// plane keeps an orthonormal frame and refuses a zero normal, both follow their parent transform.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include <vtkCallbackCommand.h>
#include <vtkNew.h>

#include "vtkRPCutPlaneNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPTrajectoryNode.h"

namespace {
int CountModified(vtkObject* object, const std::function<void()>& change) {
  int count = 0;
  vtkNew<vtkCallbackCommand> callback;
  callback->SetClientData(&count);
  callback->SetCallback([](vtkObject*, unsigned long, void* clientData, void*) { ++*static_cast<int*>(clientData); });
  const unsigned long tag = object->AddObserver(vtkCommand::ModifiedEvent, callback);
  change();
  object->RemoveObserver(tag);
  return count;
}
}  // namespace

TEST(PlanNodes, ATrajectoryHoldsItsEntryAndTargetAndChangesInOneEvent) {
  vtkNew<vtkRPTrajectoryNode> tunnel;
  EXPECT_FALSE(tunnel->IsComplete());
  EXPECT_EQ(tunnel->GetLengthMm(), 0);
  const double entry[3] = {0, 0, 0}, target[3] = {3, 4, 0}, third[3] = {9, 9, 9};
  EXPECT_EQ(CountModified(tunnel, [&] { tunnel->SetEntryAndTarget(entry, target); }), 1);
  EXPECT_TRUE(tunnel->IsComplete());
  EXPECT_EQ(tunnel->GetLengthMm(), 5);
  EXPECT_EQ(tunnel->AddControlPoint(third), -1);  // a line has two points
  EXPECT_EQ(tunnel->GetNumberOfControlPoints(), 2);
  EXPECT_STREQ(tunnel->GetMarkupsType(), "Line");
  tunnel->SetToolDiameterMm(-1);  // refused
  tunnel->SetToolDiameterMm(std::nan(""));
  EXPECT_EQ(tunnel->GetToolDiameterMm(), 2.0);
  tunnel->SetNthControlPointLocked(1, true);
  EXPECT_FALSE(tunnel->SetTarget(third));

  vtkNew<vtkRPScrewNode> screw;
  screw->SetScrewLengthMm(0);  // refused
  screw->SetHeadLengthMm(0);   // a headless screw
  EXPECT_EQ(screw->GetScrewLengthMm(), 40);
  EXPECT_EQ(screw->GetHeadLengthMm(), 0);
  EXPECT_TRUE(screw->IsA("vtkRPTrajectoryNode"));
}

TEST(PlanNodes, ACutPlaneKeepsAnOrthonormalFrameAndRefusesAZeroNormal) {
  vtkNew<vtkRPCutPlaneNode> plane;
  const double origin[3] = {1, 2, 3}, zero[3] = {0, 0, 0}, tilted[3] = {0, 3, 4};
  EXPECT_TRUE(plane->SetOrigin(origin));
  EXPECT_FALSE(plane->SetNormal(zero));
  const double notANumber[3] = {std::nan(""), 0, 1};
  EXPECT_FALSE(plane->SetNormal(notANumber));
  double n[3], x[3], y[3];
  plane->GetNormal(n);
  EXPECT_EQ(n[2], 1);
  EXPECT_TRUE(plane->SetNormal(tilted));
  plane->GetNormal(n), plane->GetXAxis(x), plane->GetYAxis(y);
  EXPECT_NEAR(n[1], 0.6, 1e-15);
  EXPECT_NEAR(n[2], 0.8, 1e-15);
  EXPECT_NEAR(x[0] * n[0] + x[1] * n[1] + x[2] * n[2], 0, 1e-15);
  EXPECT_NEAR(x[0] * x[0] + x[1] * x[1] + x[2] * x[2], 1, 1e-15);
  EXPECT_NEAR(y[0] * n[0] + y[1] * n[1] + y[2] * n[2], 0, 1e-15);
  EXPECT_FALSE(plane->SetXAxis(tilted));  // along the normal
  EXPECT_EQ(plane->AddControlPoint(origin), -1);  // one point: the origin
  // Turning the normal onto the old x axis keeps a valid frame.
  const double alongX[3] = {x[0], x[1], x[2]};
  EXPECT_TRUE(plane->SetNormal(alongX));
  plane->GetNormal(n), plane->GetXAxis(x);
  EXPECT_NEAR(x[0] * n[0] + x[1] * n[1] + x[2] * n[2], 0, 1e-15);
}

TEST(PlanNodes, PlansFollowTheirParentTransform) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> transform;
  // Rotation of 90 degrees about S, then a shift; and a scale of 2 along R to test the normal.
  const double m[16] = {0, -1, 0, 10, 2, 0, 0, 0, 0, 0, 1, 5, 0, 0, 0, 1};
  transform->SetMatrixTransformToParent(m);
  scene->AddNode(transform);
  vtkNew<vtkRPTrajectoryNode> tunnel;
  vtkNew<vtkRPCutPlaneNode> plane;
  scene->AddNode(tunnel);
  scene->AddNode(plane);
  tunnel->SetAndObserveTransformNodeID(transform->GetID());
  plane->SetAndObserveTransformNodeID(transform->GetID());
  const double entry[3] = {1, 0, 0}, target[3] = {1, 0, 10};
  tunnel->SetEntryAndTarget(entry, target);
  double world[3];
  tunnel->GetEntryWorld(world);
  EXPECT_EQ(world[0], 10);
  EXPECT_EQ(world[1], 2);
  EXPECT_EQ(world[2], 5);
  const double worldTarget[3] = {10, 2, 20};
  ASSERT_TRUE(tunnel->SetNthControlPointPositionWorld(1, worldTarget));
  double local[3];
  tunnel->GetTarget(local);
  EXPECT_NEAR(local[0], 1, 1e-15);
  EXPECT_NEAR(local[2], 15, 1e-15);
  // A plane x = y (normal (1,-1,0)/sqrt 2) maps to the world plane through the mapped points:
  // (x, y) -> (-y, 2x), so the world normal is along (1, 1/2, 0) normalised... checked by points.
  const double origin[3] = {0, 0, 0}, normal[3] = {1, -1, 0};
  plane->SetOrigin(origin);
  plane->SetNormal(normal);
  double n[3], o[3];
  plane->GetNormalWorld(n);
  plane->GetOriginWorld(o);
  // Two points of the local plane, mapped: (1,1,0) -> (9, 2, 5), (0,0,1) -> (10, 0, 6).
  const double p1[3] = {9, 2, 5}, p2[3] = {10, 0, 6};
  for (const double* p : {p1, p2}) EXPECT_NEAR((p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2], 0, 1e-12);
  EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1, 1e-15);
}
