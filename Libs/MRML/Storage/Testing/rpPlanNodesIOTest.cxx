// Plan nodes (trajectory, screw, cut plane) and structures at risk (protected models and
// segments) in every file they travel in: .mrk.json (Slicer's "Line" and "Plane" with our fields
// as attributes), .rpscene, .mrml/.mrb and .seg.nrrd. Round trips are exact; the LPS keys and
// matrices are checked against hand-negated values; Slicer's other plane forms (3 points, no
// matrices) read as Slicer computes them. Slicer's own library reading these files is
// Testing/Oracles/SlicerMRML (case plan-markups).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>

#include "rpMarkupsFormat.h"
#include "rpMarkupsIO.h"
#include "rpMrmlScene.h"
#include "rpNodeStorage.h"
#include "rpSceneIO.h"
#include "rpTestOutput.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

using rptest::TestDir;

namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

template <class T>
T* Named(vtkRPScene* scene, const std::string& name) {
  return T::SafeDownCast(scene->GetFirstNodeByName(name));
}

void ExpectPoint(const double* got, double r, double a, double s, double tolerance = 0) {
  EXPECT_NEAR(got[0], r, tolerance);
  EXPECT_NEAR(got[1], a, tolerance);
  EXPECT_NEAR(got[2], s, tolerance);
}

void FillTunnel(vtkRPTrajectoryNode* tunnel) {
  tunnel->SetName("Tibial tunnel");
  const double entry[3] = {10.5, -20.25, 30.125}, target[3] = {-5.0, 12.5, -8.75};
  tunnel->SetEntryAndTarget(entry, target);
  tunnel->SetToolDiameterMm(4.5);
  tunnel->SetIntendedTissue("trabecular bone");
  tunnel->SetColor(0.1, 0.7, 0.35);
  tunnel->SetPlannedOn("grid 146x176x150");
  tunnel->SetAttribute("Lab.Note", "50% done; \"checked\"");
}

void FillScrew(vtkRPScrewNode* screw) {
  screw->SetName("Screw 1");
  const double entry[3] = {1, 2, 3}, target[3] = {4, -5, 36};
  screw->SetEntryAndTarget(entry, target);
  screw->SetToolDiameterMm(3.2);
  screw->SetScrewDiameterMm(6.5);
  screw->SetScrewLengthMm(35);
  screw->SetHeadDiameterMm(11);
  screw->SetHeadLengthMm(0);
}

void FillPlane(vtkRPCutPlaneNode* plane) {
  plane->SetName("Resection");
  const double origin[3] = {3.0, -4.0, 25.0}, normal[3] = {0.2, -0.3, 0.9}, x[3] = {1, 0, 0};
  plane->SetOrigin(origin);
  plane->SetNormal(normal);
  plane->SetXAxis(x);
  plane->SetSize(80, 60);
}

void ExpectSameTunnel(vtkRPTrajectoryNode* a, vtkRPTrajectoryNode* b) {
  ASSERT_TRUE(b->IsComplete());
  double pa[3], pb[3];
  a->GetEntry(pa), b->GetEntry(pb);
  ExpectPoint(pb, pa[0], pa[1], pa[2]);  // exact
  a->GetTarget(pa), b->GetTarget(pb);
  ExpectPoint(pb, pa[0], pa[1], pa[2]);
  EXPECT_EQ(b->GetToolDiameterMm(), a->GetToolDiameterMm());
  EXPECT_EQ(b->GetIntendedTissue(), a->GetIntendedTissue());
  EXPECT_EQ(b->GetPlannedOn(), a->GetPlannedOn());
  ExpectPoint(b->GetColor(), a->GetColor()[0], a->GetColor()[1], a->GetColor()[2]);
  EXPECT_EQ(b->GetAttribute("Lab.Note"), a->GetAttribute("Lab.Note"));
  EXPECT_EQ(b->GetNthControlPoint(0).Label, "entry");
  EXPECT_EQ(b->GetNthControlPoint(1).Label, "target");
}

void ExpectSamePlane(vtkRPCutPlaneNode* a, vtkRPCutPlaneNode* b, double tolerance) {
  ASSERT_TRUE(b->IsComplete());
  double pa[3], pb[3];
  a->GetOrigin(pa), b->GetOrigin(pb);
  ExpectPoint(pb, pa[0], pa[1], pa[2], tolerance);
  a->GetNormal(pa), b->GetNormal(pb);
  ExpectPoint(pb, pa[0], pa[1], pa[2], tolerance);
  a->GetXAxis(pa), b->GetXAxis(pb);
  ExpectPoint(pb, pa[0], pa[1], pa[2], tolerance);
  EXPECT_NEAR(b->GetSize()[0], a->GetSize()[0], tolerance);
  EXPECT_NEAR(b->GetSize()[1], a->GetSize()[1], tolerance);
}

}  // namespace

TEST(PlanNodes, ATrajectoryIsASlicerLineWithOurFieldsAsAttributes) {
  const auto dir = TestDir("trajectory");
  vtkNew<vtkRPTrajectoryNode> tunnel;
  FillTunnel(tunnel);
  const std::string path = (dir / "tunnel.mrk.json").string();
  std::string error;
  ASSERT_TRUE(rp::SaveDataFile(tunnel, path, error)) << error;

  const auto doc = nlohmann::json::parse(ReadText(path));
  const auto& m = doc["markups"][0];
  EXPECT_EQ(m["type"], "Line");
  EXPECT_EQ(m["coordinateSystem"], "LPS");
  ASSERT_EQ(m["controlPoints"].size(), 2u);
  EXPECT_DOUBLE_EQ(m["controlPoints"][0]["position"][0].get<double>(), -10.5);  // LPS: x, y negated
  EXPECT_DOUBLE_EQ(m["controlPoints"][0]["position"][1].get<double>(), 20.25);
  EXPECT_DOUBLE_EQ(m["controlPoints"][1]["position"][2].get<double>(), -8.75);
  ASSERT_EQ(m["measurements"].size(), 1u);
  EXPECT_EQ(m["measurements"][0]["name"], "length");
  EXPECT_NEAR(m["measurements"][0]["value"].get<double>(), tunnel->GetLengthMm(), 1e-12);
  EXPECT_EQ(m["attributes"]["RoboPlan.toolDiameterMm"], "4.5");
  EXPECT_EQ(m["attributes"]["RoboPlan.intendedTissue"], "trabecular bone");
  EXPECT_EQ(m["attributes"]["Lab.Note"], "50% done; \"checked\"");
  EXPECT_FALSE(m["attributes"].contains("RoboPlan.color"));  // Slicer's display block holds it
  EXPECT_FALSE(m["attributes"].contains("RoboPlan.Class"));   // a line is a trajectory anyway
  EXPECT_EQ(m["name"], "Tibial tunnel");

  vtkNew<vtkRPScene> scene;
  vtkRPNode* loaded = rp::LoadDataFile(scene, path, error);
  ASSERT_NE(loaded, nullptr) << error;
  ASSERT_TRUE(loaded->IsA("vtkRPTrajectoryNode"));
  EXPECT_FALSE(loaded->IsA("vtkRPScrewNode"));
  ExpectSameTunnel(tunnel, vtkRPTrajectoryNode::SafeDownCast(loaded));
}

TEST(PlanNodes, AScrewComesBackAsAScrewWithItsSizes) {
  const auto dir = TestDir("screw");
  vtkNew<vtkRPScrewNode> screw;
  FillScrew(screw);
  const std::string path = (dir / "screw.mrk.json").string();
  std::string error;
  ASSERT_TRUE(rp::SaveDataFile(screw, path, error)) << error;
  EXPECT_EQ(nlohmann::json::parse(ReadText(path))["markups"][0]["attributes"]["RoboPlan.Class"], "vtkRPScrewNode");
  vtkNew<vtkRPScene> scene;
  auto* back = vtkRPScrewNode::SafeDownCast(rp::LoadDataFile(scene, path, error));
  ASSERT_NE(back, nullptr) << error;
  EXPECT_EQ(back->GetScrewDiameterMm(), 6.5);
  EXPECT_EQ(back->GetScrewLengthMm(), 35);
  EXPECT_EQ(back->GetHeadDiameterMm(), 11);
  EXPECT_EQ(back->GetHeadLengthMm(), 0);
  EXPECT_EQ(back->GetToolDiameterMm(), 3.2);
}

TEST(PlanNodes, ACutPlaneIsASlicerPointNormalPlaneInLPS) {
  const auto dir = TestDir("plane");
  vtkNew<vtkRPCutPlaneNode> plane;
  FillPlane(plane);
  const std::string path = (dir / "plane.mrk.json").string();
  std::string error;
  ASSERT_TRUE(rp::SaveDataFile(plane, path, error)) << error;

  const auto m = nlohmann::json::parse(ReadText(path))["markups"][0];
  EXPECT_EQ(m["type"], "Plane");
  EXPECT_EQ(m["planeType"], "pointNormal");
  EXPECT_EQ(m["sizeMode"], "absolute");
  double n[3];
  plane->GetNormal(n);
  EXPECT_DOUBLE_EQ(m["normal"][0].get<double>(), -n[0]);
  EXPECT_DOUBLE_EQ(m["normal"][1].get<double>(), -n[1]);
  EXPECT_DOUBLE_EQ(m["normal"][2].get<double>(), n[2]);
  EXPECT_DOUBLE_EQ(m["center"][0].get<double>(), -3.0);
  // baseToNode in LPS: its first two rows negated; the origin is its translation column.
  EXPECT_DOUBLE_EQ(m["baseToNode"][3].get<double>(), -3.0);
  EXPECT_DOUBLE_EQ(m["baseToNode"][7].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(m["baseToNode"][11].get<double>(), 25.0);
  EXPECT_DOUBLE_EQ(m["baseToNode"][2].get<double>(), -n[0]);  // the normal is the third column
  EXPECT_DOUBLE_EQ(m["baseToNode"][10].get<double>(), n[2]);
  EXPECT_EQ(m["objectToBase"][0].get<double>(), -1.0);
  EXPECT_EQ(m["size"][0].get<double>(), 80.0);
  EXPECT_EQ(m["planeBounds"][3].get<double>(), 30.0);
  ASSERT_EQ(m["controlPoints"].size(), 1u);

  vtkNew<vtkRPScene> scene;
  auto* back = vtkRPCutPlaneNode::SafeDownCast(rp::LoadDataFile(scene, path, error));
  ASSERT_NE(back, nullptr) << error;
  ExpectSamePlane(plane, back, 1e-15);
}

TEST(PlanNodes, SlicersOtherPlaneFormsReadAsSlicerComputesThem) {
  const auto dir = TestDir("plane-forms");
  const std::string schema =
      R"("@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.0.json#")";
  // A 3-point plane without matrices (schema 1.0.0): origin p0, x along p1 - p0, normal
  // (p1 - p0) x (p2 - p0) (Slicer's CalculateAxesFromPoints). LPS: x, y negated.
  const std::string threePoints = WriteText((dir / "three.mrk.json").string(), "{" + schema + R"(, "markups": [{
      "type": "Plane", "coordinateSystem": "LPS", "controlPoints": [
        {"position": [-1, -2, 3]}, {"position": [-11, -2, 3]}, {"position": [-1, -12, 3]}]}]})");
  vtkNew<vtkRPCutPlaneNode> plane;
  std::string error;
  ASSERT_TRUE(rp::ReadMarkupsJson(threePoints, plane, error)) << error;
  double p[3];
  plane->GetOrigin(p);
  ExpectPoint(p, 1, 2, 3);
  plane->GetXAxis(p);
  ExpectPoint(p, 1, 0, 0);
  plane->GetNormal(p);
  ExpectPoint(p, 0, 0, 1);
  EXPECT_EQ(plane->GetNumberOfControlPoints(), 1);  // the origin; our plane is point-normal

  // RAS, a point and a normal key only.
  const std::string pointNormal = WriteText((dir / "pn.mrk.json").string(), "{" + schema + R"(, "markups": [{
      "type": "Plane", "coordinateSystem": "RAS", "planeType": "pointNormal", "normal": [0, 3, 4],
      "planeBounds": [-5, 15, -2, 2], "controlPoints": [{"position": [7, 8, 9]}]}]})");
  ASSERT_TRUE(rp::ReadMarkupsJson(pointNormal, plane, error)) << error;
  plane->GetOrigin(p);
  ExpectPoint(p, 7, 8, 9);
  plane->GetNormal(p);
  ExpectPoint(p, 0, 0.6, 0.8, 1e-15);
  EXPECT_EQ(plane->GetSize()[0], 20);
  EXPECT_EQ(plane->GetSize()[1], 4);
}

TEST(PlanNodes, AFileOfAnotherKindIsNamedAndTheNodeKept) {
  const auto dir = TestDir("kinds");
  vtkNew<vtkRPTrajectoryNode> tunnel;
  FillTunnel(tunnel);
  vtkNew<vtkRPCutPlaneNode> plane;
  FillPlane(plane);
  const std::string linePath = (dir / "line.mrk.json").string(), planePath = (dir / "plane.mrk.json").string();
  std::string error;
  ASSERT_TRUE(rp::SaveDataFile(tunnel, linePath, error)) << error;
  ASSERT_TRUE(rp::SaveDataFile(plane, planePath, error)) << error;
  EXPECT_FALSE(rp::ReadMarkupsJson(linePath, plane, error));
  EXPECT_NE(error.find("'Line', expected 'Plane'"), std::string::npos) << error;
  vtkNew<vtkRPFiducialListNode> list;
  EXPECT_FALSE(rp::ReadMarkupsJson(planePath, list, error));
  EXPECT_NE(error.find("'Plane', expected 'Fiducial'"), std::string::npos) << error;
  EXPECT_FALSE(rp::SaveDataFile(tunnel, (dir / "line.fcsv").string(), error));
  EXPECT_NE(error.find("only point lists"), std::string::npos) << error;
  double p[3];
  plane->GetOrigin(p);
  ExpectPoint(p, 3, -4, 25);  // untouched

  // A zero normal in a file is refused, naming the file.
  const std::string zero = WriteText((dir / "zero.mrk.json").string(), R"({"@schema": "markups-schema-v1.0.3.json#",
      "markups": [{"type": "Plane", "normal": [0, 0, 0], "controlPoints": [{"position": [1, 2, 3]}]}]})");
  EXPECT_FALSE(rp::ReadMarkupsJson(zero, plane, error));
  EXPECT_NE(error.find("zero.mrk.json"), std::string::npos) << error;
  EXPECT_NE(error.find("normal"), std::string::npos) << error;
}

TEST(PlanNodes, ProtectedStructuresTravelOnTheirModelAndSegment) {
  const auto dir = TestDir("protection");
  vtkNew<vtkRPSegmentationNode> segmentation;
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(6, 5, 4);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* voxels = static_cast<unsigned char*>(labels->GetScalarPointer());
  for (int i = 0; i < 120; ++i) voxels[i] = static_cast<unsigned char>(i % 3);
  segmentation->SetImageData(labels);
  rp::Segment bone, nerve;
  bone.ID = "tibia", bone.Name = "Tibia", bone.LabelValue = 1, bone.TissueClass = "bone";
  nerve.ID = "nerve", nerve.Name = "Peroneal nerve", nerve.LabelValue = 2;
  nerve.Protection = {true, 2.5};
  segmentation->SetSegment(bone);
  segmentation->SetSegment(nerve);
  const std::string segPath = (dir / "labels.seg.nrrd").string();
  std::string error;
  ASSERT_TRUE(rp::SaveDataFile(segmentation, segPath, error)) << error;
  EXPECT_NE(ReadText(segPath).find("RoboPlan.Protected:true|RoboPlan.SafetyMarginMm:2.5|"), std::string::npos);
  vtkNew<vtkRPScene> scene;
  auto* back = vtkRPSegmentationNode::SafeDownCast(rp::LoadDataFile(scene, segPath, error));
  ASSERT_NE(back, nullptr) << error;
  EXPECT_FALSE(back->GetSegmentByID("tibia")->Protection.Protected);
  EXPECT_TRUE(back->GetSegmentByID("nerve")->Protection.Protected);
  EXPECT_EQ(back->GetSegmentByID("nerve")->Protection.SafetyMarginMm, 2.5);

  // A margin that is not a number is an error naming the segment's field.
  std::string text = ReadText(segPath);
  text.replace(text.find("SafetyMarginMm:2.5"), 18, "SafetyMarginMm:2,5");
  const std::string bad = WriteText((dir / "bad.seg.nrrd").string(), text);
  EXPECT_EQ(rp::LoadDataFile(scene, bad, error), nullptr);
  EXPECT_NE(error.find("Segment1_Tags"), std::string::npos) << error;
  EXPECT_NE(error.find("2,5"), std::string::npos) << error;
}

// Every plan node and both kinds of structure at risk through .rpscene and .mrml, with the
// screw's link to its model and a trajectory under a transform.
TEST(PlanNodes, APlanRoundTripsThroughRpsceneMrmlAndMrb) {
  const auto dir = TestDir("scenes");
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> planToCT;
  planToCT->SetName("PlanToCT");
  const double m[16] = {0, -1, 0, 5, 1, 0, 0, -3, 0, 0, 1, 12, 0, 0, 0, 1};
  planToCT->SetMatrixTransformToParent(m);
  scene->AddNode(planToCT);
  vtkNew<vtkRPTrajectoryNode> tunnel;
  FillTunnel(tunnel);
  scene->AddNode(tunnel);
  tunnel->SetAndObserveTransformNodeID(planToCT->GetID());
  vtkNew<vtkRPScrewNode> screw;
  FillScrew(screw);
  scene->AddNode(screw);
  vtkNew<vtkRPModelNode> screwModel, vessels;
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  screwModel->SetName("Screw 1 model");
  screwModel->SetPolyData(sphere->GetOutput());
  scene->AddNode(screwModel);
  screw->SetNodeReferenceID(vtkRPScrewNode::ScrewModelRole(), screwModel->GetID());
  vessels->SetName("Popliteal vessels");
  vessels->SetPolyData(sphere->GetOutput());
  vessels->SetProtection({true, 3.0});
  scene->AddNode(vessels);
  vtkNew<vtkRPCutPlaneNode> plane;
  FillPlane(plane);
  scene->AddNode(plane);

  for (const std::string name : {"plan.rpscene", "plan.mrml", "plan.mrb"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    std::string error;
    rp::SceneTransferReport report;
    if (name == "plan.rpscene") ASSERT_TRUE(rp::SaveScene(scene, path, error)) << error;
    else ASSERT_TRUE(name == "plan.mrml" ? rp::WriteMrmlScene(scene, path, report) : rp::WriteMrmlBundle(scene, path, report))
        << report.FirstProblem();
    vtkNew<vtkRPScene> back;
    if (name == "plan.rpscene") {
      const rp::SceneLoadReport loaded = rp::LoadScene(back, path);
      ASSERT_TRUE(loaded.Ok && loaded.Problems.empty()) << loaded.Error;
    } else {
      ASSERT_TRUE(name == "plan.mrml" ? rp::ReadMrmlScene(path, back, report) : rp::ReadMrmlBundle(path, back, report))
          << report.Error;
      EXPECT_TRUE(report.Skipped.empty()) << report.FirstProblem();
      EXPECT_TRUE(report.Warnings.empty()) << report.Warnings.front();
    }
    auto* tunnelBack = Named<vtkRPTrajectoryNode>(back, "Tibial tunnel");
    ASSERT_NE(tunnelBack, nullptr);
    ExpectSameTunnel(tunnel, tunnelBack);
    ASSERT_NE(tunnelBack->GetParentTransformNode(), nullptr);
    EXPECT_EQ(tunnelBack->GetParentTransformNode()->GetName(), "PlanToCT");
    double world[3], worldBack[3];
    tunnel->GetTargetWorld(world), tunnelBack->GetTargetWorld(worldBack);
    ExpectPoint(worldBack, world[0], world[1], world[2], 1e-12);
    auto* screwBack = Named<vtkRPScrewNode>(back, "Screw 1");
    ASSERT_NE(screwBack, nullptr);
    EXPECT_EQ(screwBack->GetScrewLengthMm(), 35);
    ASSERT_NE(screwBack->GetNodeReference(vtkRPScrewNode::ScrewModelRole()), nullptr);
    EXPECT_EQ(screwBack->GetNodeReference(vtkRPScrewNode::ScrewModelRole())->GetName(), "Screw 1 model");
    auto* vesselsBack = Named<vtkRPModelNode>(back, "Popliteal vessels");
    ASSERT_NE(vesselsBack, nullptr);
    EXPECT_TRUE(vesselsBack->GetProtection().Protected);
    EXPECT_EQ(vesselsBack->GetProtection().SafetyMarginMm, 3.0);
    EXPECT_FALSE(Named<vtkRPModelNode>(back, "Screw 1 model")->GetProtection().Protected);
    auto* planeBack = Named<vtkRPCutPlaneNode>(back, "Resection");
    ASSERT_NE(planeBack, nullptr);
    ExpectSamePlane(plane, planeBack, 1e-15);
  }
}

TEST(PlanNodes, TheMrmlCarriesOurFieldsAsNodeAttributesAndSlicersTags) {
  const auto dir = TestDir("mrml-text");
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPScrewNode> screw;
  FillScrew(screw);
  scene->AddNode(screw);
  vtkNew<vtkRPCutPlaneNode> plane;
  FillPlane(plane);
  scene->AddNode(plane);
  const std::string path = (dir / "plan.mrml").string();
  rp::SceneTransferReport report;
  ASSERT_TRUE(rp::WriteMrmlScene(scene, path, report)) << report.FirstProblem();
  const std::string text = ReadText(path);
  for (const char* expected :
       {"<MarkupsLine", "RoboPlan.Class:vtkRPScrewNode", "RoboPlan.screwLengthMm:35", "RoboPlan.toolDiameterMm:3.2",
        "<MarkupsPlane", "MarkupsPlaneJsonStorage", "MarkupsPlaneDisplay", "<MarkupsDisplay", "MarkupsJsonStorage"})
    EXPECT_NE(text.find(expected), std::string::npos) << expected;
  // The plane's axes and size live in its .mrk.json, not repeated as attributes.
  EXPECT_EQ(text.find("RoboPlan.normal"), std::string::npos);
  EXPECT_EQ(text.find("RoboPlan.sizeMm"), std::string::npos);
}
