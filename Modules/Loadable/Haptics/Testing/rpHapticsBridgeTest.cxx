// Scene bridge: haptic meshes from model nodes flagged haptic (RAS through their transforms),
// HapticDeviceToRAS with workspace scale, tool nodes updated from the servo state on the main
// thread, a live session that rebuilds its scene when a model changes, a tracked tool driving the
// proxy in RAS, and the `haptics` command through the module's logic.
#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkCallbackCommand.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpHapticSession.h"
#include "rpHapticsCommand.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSimulatedDevice.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"

namespace {
vtkRPModelNode* AddModel(vtkRPScene* scene, const char* name, const char* tissue, bool haptic, const rp::TriangleMesh& m) {
  vtkNew<vtkRPModelNode> model;
  model->SetName(name);
  model->SetTissueClass(tissue);
  model->SetHaptic(haptic);
  model->SetPolyData(rp::TriangleMeshToPolyData(m));
  scene->AddNode(model);
  return model;
}
}  // namespace

TEST(HapticsBridge, HapticModelsOnlyInRASThroughTransforms) {
  vtkNew<vtkRPScene> scene;
  vtkRPModelNode* bone = AddModel(scene, "Femur", "bone", true, rp::shapes::Box({0, 0, 0}, {10, 10, 10}));
  AddModel(scene, "Display only", "bone", false, rp::shapes::Box({0, 0, 0}, {1, 1, 1}));
  AddModel(scene, "Fat", "fat", true, rp::shapes::Sphere({50, 0, 0}, 5, 2));
  vtkNew<vtkRPLinearTransformNode> shift;
  shift->SetName("FemurToRAS");
  const double m[16] = {1, 0, 0, 100, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  shift->SetMatrixTransformToParent(m);
  scene->AddNode(shift);
  const unsigned long before = rp::HapticMeshesSignature(scene);
  ASSERT_TRUE(bone->SetAndObserveTransformNodeID(shift->GetID()));
  EXPECT_NE(rp::HapticMeshesSignature(scene), before);

  std::vector<std::string> warnings;
  std::vector<rp::HapticMeshInput> meshes = rp::CollectHapticMeshes(scene, warnings);
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_TRUE(warnings.empty());
  const rp::HapticMeshInput& femur = meshes[0].Name == "Femur" ? meshes[0] : meshes[1];
  EXPECT_EQ(femur.TissueClass, "bone");
  ASSERT_EQ(femur.Mesh.Triangles.size(), 12u);
  double minX = 1e9;
  for (const auto& p : femur.Mesh.Points) minX = std::min(minX, p.x);
  EXPECT_DOUBLE_EQ(minX, 100.0);  // moved by the parent transform

  std::string error;
  auto built = rp::HapticScene::Build(meshes, rp::MaterialTable::Defaults(), warnings, error);
  ASSERT_TRUE(built) << error;
  rp::ClosestPointHit hit;
  ASSERT_TRUE(built->Tree.ClosestPoint({105, 5, 20}, HUGE_VAL, hit));
  EXPECT_EQ(built->MaterialOf(hit.Triangle).Tissue, "bone");
  EXPECT_NEAR(hit.Distance2, 100.0, 1e-9);

  // A model without polygons is skipped with a warning naming it.
  vtkNew<vtkRPModelNode> empty;
  empty->SetName("Empty");
  empty->SetHaptic(true);
  scene->AddNode(empty);
  warnings.clear();
  EXPECT_EQ(rp::CollectHapticMeshes(scene, warnings).size(), 2u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("Empty"), std::string::npos);
}

TEST(HapticsBridge, DeviceToRASWithWorkspaceScale) {
  vtkNew<vtkRPScene> scene;
  rp::DeviceToScene xf;
  EXPECT_FALSE(rp::ReadDeviceToScene(scene, xf));
  EXPECT_EQ(xf.Scale, 1.0);
  vtkNew<vtkRPLinearTransformNode> node;
  node->SetName(rp::HapticDeviceToRASName);
  // 2x scale with a 90° rotation about z, then a translation.
  const double m[16] = {0, -2, 0, 10, 2, 0, 0, 20, 0, 0, 2, 30, 0, 0, 0, 1};
  node->SetMatrixTransformToParent(m);
  scene->AddNode(node);
  ASSERT_TRUE(rp::ReadDeviceToScene(scene, xf));
  EXPECT_DOUBLE_EQ(xf.Scale, 2.0);
  const rp::Vec3 ras = xf.DeviceToRAS.Apply(rp::Vec3{1, 0, 0} * xf.Scale);
  EXPECT_NEAR(ras.x, 10, 1e-12);
  EXPECT_NEAR(ras.y, 22, 1e-12);
  EXPECT_NEAR(ras.z, 30, 1e-12);
}

TEST(HapticsBridge, ToolNodesGetTheStateInOneModifiedEvent) {
  vtkNew<vtkRPScene> scene;
  rp::HapticState state;
  state.Hip = {1, 2, 3};
  state.Proxy = {1, 2, 4};
  state.Force = {0, 0, 1.5};
  state.Contacts = 1;
  state.Label = 0;
  state.Time = 2.5;
  rp::UpdateToolNodes(scene, state, {"bone"});
  auto* hip = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticInterfacePointName));
  auto* proxy = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticProxyName));
  ASSERT_TRUE(hip && proxy);
  EXPECT_EQ(hip->GetMatrixTransformToParent()->GetElement(2, 3), 3.0);
  EXPECT_EQ(proxy->GetMatrixTransformToParent()->GetElement(2, 3), 4.0);
  EXPECT_EQ(proxy->GetAttribute("Tissue"), "bone");
  EXPECT_EQ(proxy->GetAttribute("Force"), "0.0000,0.0000,1.5000");
  EXPECT_EQ(hip->GetTimestamp(), 2.5);
  int events = 0;
  vtkNew<vtkCallbackCommand> counter;
  counter->SetClientData(&events);
  counter->SetCallback([](vtkObject*, unsigned long, void* data, void*) { ++*static_cast<int*>(data); });
  proxy->AddObserver(vtkCommand::ModifiedEvent, counter);
  state.Proxy = {5, 5, 5};
  state.Force = {1, 0, 0};
  rp::UpdateToolNodes(scene, state, {"bone"});
  EXPECT_EQ(events, 1);
  EXPECT_EQ(scene->GetNumberOfNodes(), 2);  // reused, not duplicated
}

TEST(HapticsBridge, SessionRendersAndRebuildsWhenAModelChanges) {
  vtkNew<vtkRPScene> scene;
  vtkRPModelNode* slab = AddModel(scene, "Slab", "bone", true, rp::shapes::Box({-40, -40, -20}, {40, 40, 0}));
  rp::SimulatedDevice device;
  rp::Pose pose;
  pose.T = {0, 0, 10};
  device.SetManualPose(pose);
  rp::HapticSession session(device);
  rp::HapticSession::Options options;
  options.RampSeconds = 0.01;
  std::string error;
  ASSERT_TRUE(session.Start(scene, options, error)) << error;
  EXPECT_EQ(session.SceneTriangles(), 12u);
  // The "viewer" pushes the stylus 1 mm into the slab.
  for (int i = 0; i <= 20; ++i) {
    pose.T = {0, 0, 10 - 11.0 * i / 20};
    device.SetManualPose(pose);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(session.Update());
  auto* proxy = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticProxyName));
  ASSERT_TRUE(proxy);
  EXPECT_EQ(proxy->GetAttribute("Tissue"), "bone");
  EXPECT_NEAR(proxy->GetMatrixTransformToParent()->GetElement(2, 3), 0.0, 1e-3);
  // Replace the mesh by a slab 5 mm higher: the session rebuilds off the servo thread and swaps.
  slab->SetPolyData(rp::TriangleMeshToPolyData(rp::shapes::Box({-40, -40, -20}, {40, 40, 5})));
  session.Update();
  for (int i = 0; i < 100 && session.ScenesBuilt() < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    session.Update();
  }
  EXPECT_EQ(session.ScenesBuilt(), 2u);
  // The stylus is now 6 mm under the new top, reached from inside the new slab: the proxy only
  // meets surfaces it approaches from outside, so no contact (no violent kick on a scene swap).
  // Lift and press again to touch the new top.
  for (int i = 0; i <= 20; ++i) {
    pose.T = {0, 0, -1 + 21.0 * i / 20};
    device.SetManualPose(pose);
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
  for (int i = 0; i <= 20; ++i) {
    pose.T = {0, 0, 20 - 16.0 * i / 20};
    device.SetManualPose(pose);
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  session.Update();
  EXPECT_NEAR(proxy->GetMatrixTransformToParent()->GetElement(2, 3), 5.0, 1e-3);
  session.Stop();
  EXPECT_EQ(rp::Norm(device.LastForce()), 0.0);
}

TEST(HapticsLogic, SimulatedStylusFromTheViewerTouchesTheScene) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPHapticsLogic> logic;
  std::string error;
  EXPECT_FALSE(logic->StartSimulated(error));  // no scene
  logic->SetScene(scene);
  EXPECT_FALSE(logic->StartSimulated(error));  // no haptic model
  EXPECT_NE(error.find("no haptic models"), std::string::npos) << error;
  AddModel(scene, "Skin", "skin", true, rp::shapes::Box({-40, -40, -20}, {40, 40, 0}));
  ASSERT_TRUE(logic->StartSimulated(error)) << error;
  EXPECT_TRUE(logic->IsRunning());
  vtkNew<vtkMatrix4x4> pose;
  for (int i = 0; i <= 20; ++i) {  // the mouse drags the stylus 1 mm into the skin
    pose->SetElement(2, 3, 10 - 11.0 * i / 20);
    logic->SetSimulatedStylusPose(pose);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // past the 0.5 s force ramp
  ASSERT_TRUE(logic->Update());
  auto* proxy = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticProxyName));
  ASSERT_TRUE(proxy);
  EXPECT_EQ(proxy->GetAttribute("Tissue"), "skin");
  double force[3];
  logic->GetLastForce(force);
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  const double kSkin = table.Materials()[table.Find("skin")].Stiffness;
  EXPECT_NEAR(force[2], kSkin * (1 + rp::GodObjectProxy::Gap), 1e-6);
  logic->Stop();
  EXPECT_FALSE(logic->IsRunning());
}

TEST(HapticsLogic, ATrackedToolDrivesTheProxy) {
  // A stylus tip tracked under TrackerToRAS drives the haptic proxy in RAS as it is: the scene's
  // HapticDeviceToRAS (rotated, translated, scaled 2x) is not applied to it; only its scale stays,
  // for the gain limits of the device the stylus stands for.
  vtkNew<vtkRPScene> scene;
  AddModel(scene, "Tibia", "bone", true, rp::shapes::Box({-40, -40, -20}, {40, 40, 0}));
  vtkNew<vtkRPLinearTransformNode> device;
  device->SetName(rp::HapticDeviceToRASName);
  const double scaled[16] = {2, 0, 0, 0, 0, 0, -2, 0, 0, 2, 0, 100, 0, 0, 0, 1};
  device->SetMatrixTransformToParent(scaled);
  scene->AddNode(device);
  vtkNew<vtkRPLinearTransformNode> tracker;
  tracker->SetName("TrackerToRAS");
  const double rz90[16] = {0, -1, 0, 5, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // tracker (x, y, z) → RAS (5 − y, x, z)
  tracker->SetMatrixTransformToParent(rz90);
  scene->AddNode(tracker);
  vtkNew<vtkRPTrackedToolNode> tip;
  tip->SetName("StylusTip");
  scene->AddNode(tip);
  ASSERT_TRUE(tip->SetAndObserveTransformNodeID(tracker->GetID()));
  auto place = [&](double z) {  // the tip at tracker (0, 5, z): RAS (0, 0, z), mid-face (no shading tilt)
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1, z, 0, 0, 0, 1};
    tip->SetMatrixTransformToParent(m);
  };
  place(10);
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  logic->SetRampSeconds(0.01);
  logic->SetFollowedNodeID(tip->GetID());
  std::string error;
  ASSERT_TRUE(logic->StartSimulated(error)) << error;
  for (int i = 0; i < 5; ++i) {
    logic->Update();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  place(-1);  // 1 mm into the bone
  for (int i = 0; i < 6; ++i) {
    logic->Update();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(logic->Update());
  auto* hip = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticInterfacePointName));
  auto* proxy = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(rp::HapticProxyName));
  ASSERT_TRUE(hip && proxy);
  EXPECT_EQ(hip->GetMatrixTransformToParent()->GetElement(0, 3), 0.0);
  EXPECT_EQ(hip->GetMatrixTransformToParent()->GetElement(1, 3), 0.0);
  EXPECT_EQ(hip->GetMatrixTransformToParent()->GetElement(2, 3), -1.0);
  EXPECT_NEAR(proxy->GetMatrixTransformToParent()->GetElement(2, 3), 0.0, 1e-3);
  EXPECT_EQ(proxy->GetAttribute("Tissue"), "bone");
  // The Omni's 0.7 N/mm through the 2x workspace scale: 0.35 N/mm in the scene, along +S in RAS.
  double force[3];
  logic->GetLastForce(force);
  EXPECT_NEAR(force[2], 0.35 * (1 + rp::GodObjectProxy::Gap), 1e-6);
  EXPECT_NEAR(force[0], 0.0, 1e-9);
  EXPECT_NEAR(force[1], 0.0, 1e-9);
  logic->Stop();
}

TEST(HapticsCommand, ProbesTheDemoSceneThroughTheLogic) {
  // `roboplan haptics` is parse → vtkRPHapticsLogic → report: the probe path over the analytic
  // scene touches both tissues, within the device's force.
  std::ostringstream out, err;
  ASSERT_EQ(rp::RunHapticsCommand({"--seconds", "2", "--json"}, nullptr, out, err), 0) << err.str();
  const nlohmann::json doc = nlohmann::json::parse(out.str());
  EXPECT_EQ(doc["device"]["profile"], "omni");
  EXPECT_GT(doc["scene"]["triangles"].get<int>(), 100);
  EXPECT_GT(doc["servo"]["ticks"].get<int>(), 1000);
  EXPECT_TRUE(doc["force"]["tissueTicks"].contains("bone")) << doc["force"].dump();
  EXPECT_GT(doc["force"]["maxN"].get<double>(), 0.2);
  EXPECT_LE(doc["force"]["maxN"].get<double>(), 3.3 + 1e-9);
  EXPECT_EQ(doc["log"]["records"].get<uint64_t>() + doc["log"]["dropped"].get<uint64_t>(), doc["servo"]["ticks"].get<uint64_t>());
  // A trajectory file that is not one: exit 2, named.
  std::ostringstream out2, err2;
  EXPECT_EQ(rp::RunHapticsCommand({"--seconds", "1", "--trajectory", "/nonexistent/path.csv"}, nullptr, out2, err2), 2);
  EXPECT_NE(err2.str().find("/nonexistent/path.csv"), std::string::npos) << err2.str();
}
