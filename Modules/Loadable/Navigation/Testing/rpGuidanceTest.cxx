// Issue 38: navigation read-outs of a tool pose against a plan (closed forms), the execution path
// readers (CSV, drilling recording, PLUS sequence), and PLUS's real recording of a stylus
// (../shared/oracles/plus-data) scored through its stylus tip against a plan, beside an
// independent computation (the sequence's text parsed here, Eigen's SVD line fit).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "rpDrillRecording.h"
#include "rpExecutionPath.h"
#include "rpExecutionScore.h"
#include "rpGuidanceReadout.h"
#include "rpNodeStorage.h"
#include "rpScoreCommand.h"
#include "rpScoredExecution.h"
#include "rpSharedData.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"
#include "rpPlannedToolScene.h"
#include "rpTestAxis.h"

namespace {

using rp::Vec3;
const std::string PlusData = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data";

std::string TempFile(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / ("rpGuidanceTest-" + name)).string();
  std::ofstream(path) << text;
  return path;
}

using rptest::Axis;

// A CSV of tip points from 1 mm right of (10, 20, 30) down −S, tilted by θ towards R, `run` mm long.
std::string TiltedPath(const std::string& name, double theta, double run) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "R,A,S\n";
  for (double s = 0; s <= run + 1e-9; s += 0.25)
    csv << 10 + 1 + s * std::sin(theta) << "," << 20 << "," << 30 - s * std::cos(theta) << "\n";
  return TempFile(name, csv.str());
}

TEST(GuidanceReadout, EntryErrorAngleDepthAndTheToolInTheTrajectorysFrame) {
  const rp::TrajectoryAxis plan = Axis({5, 6, 7}, {5, 6, -33});  // straight down, 40 mm
  const double theta = 0.2;
  // The tool's tip 1.5 mm right of the axis, 10 mm deep, tilted by θ in the R–S plane: its −z axis
  // points along (sin θ, 0, −cos θ).
  const double c = std::cos(theta), s = std::sin(theta);
  const double tip[16] = {c, 0, -s, 6.5, 0, 1, 0, 6, s, 0, c, -3, 0, 0, 0, 1};
  rp::MeshSignedDistance vessel;
  std::string error;
  ASSERT_TRUE(vessel.Build(rp::shapes::Box({10, 0, -20}, {14, 12, 0}), error)) << error;
  const rp::GuidanceReadout r = rp::ComputeReadout(plan, tip, {{"vessel", &vessel, 2.0}}, 0.5);
  ASSERT_TRUE(r.Valid);
  EXPECT_NEAR(r.LateralMm, 1.5, 1e-12);
  EXPECT_NEAR(r.DepthToTargetMm, 30, 1e-12);
  EXPECT_NEAR(r.AngleDeg, theta * 180 / M_PI, 1e-9);
  // The tool's axis goes back 10 mm of depth to the entry plane, drifting 10·tan θ to the left.
  EXPECT_NEAR(r.EntryErrorMm, std::fabs(1.5 - 10 * std::tan(theta)), 1e-9);
  EXPECT_TRUE(r.HasStructure);
  EXPECT_EQ(r.ClosestStructure, "vessel");
  EXPECT_NEAR(r.ClosestStructureMm, 10 - 6.5 - 0.5, 1e-9);
  EXPECT_FALSE(r.WithinMargin);
  // In the trajectory's frame (origin at the entry, z down the plan, x to the patient's right):
  // the tip at (1.5, 0, 10).
  EXPECT_NEAR(r.ToolTipToTrajectory[3], 1.5, 1e-12);
  EXPECT_NEAR(r.ToolTipToTrajectory[7], 0, 1e-12);
  EXPECT_NEAR(r.ToolTipToTrajectory[11], 10, 1e-12);
  const std::string line = rp::ReadoutString(r);
  EXPECT_NE(line.find("entryErrorMm="), std::string::npos);
  EXPECT_NE(line.find("closestStructure=vessel"), std::string::npos);
}

TEST(ExecutionPath, ReadsACsvOfRASPointsAndNamesABadOne) {
  rp::ExecutionPath path;
  std::string error;
  ASSERT_TRUE(rp::ReadExecutionPath(TempFile("ok.csv", "R, A, S\n1,2,3\n# a comment\n4,5,6\n"), {}, path, error)) << error;
  ASSERT_EQ(path.Points.size(), 2u);
  EXPECT_EQ(path.Points[1].z, 6);
  EXPECT_EQ(path.Kind, "csv");
  EXPECT_FALSE(rp::ReadExecutionPath(TempFile("header.csv", "x,y,z\n1,2,3\n"), {}, path, error));
  EXPECT_NE(error.find("R,A,S"), std::string::npos) << error;
  EXPECT_FALSE(rp::ReadExecutionPath(TempFile("row.csv", "R,A,S\n1,2,3\n1,2\n"), {}, path, error));
  EXPECT_NE(error.find(":3:"), std::string::npos) << error;
  EXPECT_FALSE(rp::ReadExecutionPath(TempFile("what.txt", "hello\n"), {}, path, error));
  EXPECT_NE(error.find("not a path RoboPlan scores"), std::string::npos) << error;
}

TEST(ExecutionPath, ADrillingRecordingGivesTheBurrCentreWhereTheBurrRan) {
  const std::string file = (std::filesystem::temp_directory_path() / "rpGuidanceTest-drill.txt").string();
  {
    rp::DrillRecordWriter writer;
    std::string error;
    ASSERT_TRUE(writer.Open(file, {0.2, 2, 60000, true}, error)) << error;
    for (int i = 0; i < 10; ++i) {
      rp::DrillRecord r;
      r.Time = 0.001 * (i + 1);
      r.Hip = {0, 0, -0.5 * i};
      r.Proxy = {0.1, 0, -0.5 * i};
      r.Radius = 2;
      r.Flags = i < 8 ? rp::DrillRecordFlags::BurrOn : 0u;
      writer.Add(r, 60000);
    }
  }
  rp::ExecutionPath path;
  std::string error;
  ASSERT_TRUE(rp::ReadExecutionPath(file, {}, path, error)) << error;
  EXPECT_EQ(path.Kind, "drill-recording");
  EXPECT_EQ(path.Points.size(), 8u);
  EXPECT_EQ(path.Skipped, 2u);
  EXPECT_DOUBLE_EQ(path.Points[3].x, 0.1);  // the proxy, not the hand
  EXPECT_DOUBLE_EQ(path.ToolRadiusMm, 2);
}

// "Seq_Frame<number>_<field> = <value>": the frame's number and the value, when the line is that
// field's. (Plain string reading: std::regex took 2 of this source's 16 s of compile.)
bool FrameField(const std::string& line, const std::string& field, int& frame, std::string& value) {
  const std::string prefix = "Seq_Frame", assign = "_" + field + " = ";
  if (line.rfind(prefix, 0) != 0) return false;
  size_t end = prefix.size();
  while (end < line.size() && std::isdigit(static_cast<unsigned char>(line[end]))) ++end;
  if (end == prefix.size() || line.compare(end, assign.size(), assign) != 0) return false;
  frame = std::stoi(line.substr(prefix.size(), end - prefix.size()));
  value = line.substr(end + assign.size());
  return true;
}

// The sequence's per-frame matrices parsed from its text, independently of our reader.
std::map<int, Eigen::Matrix4d> RawTransforms(const std::string& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  std::map<int, Eigen::Matrix4d> out;
  std::map<int, bool> ok;
  std::string line, value;
  int frame = 0;
  while (std::getline(in, line)) {
    if (line.rfind("ElementDataFile", 0) == 0) break;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (FrameField(line, name + "Transform", frame, value)) {
      std::istringstream values(value);
      Eigen::Matrix4d t;
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) values >> t(r, c);
      out[frame] = t;
    } else if (FrameField(line, name + "TransformStatus", frame, value)) {
      ok[frame] = value.substr(0, value.find_first_of(" \t")) == "OK";
    }
  }
  for (auto it = out.begin(); it != out.end();) it = ok[it->first] ? std::next(it) : out.erase(it);
  return out;
}

TEST(ExecutionPath, PlusRecordingScoredThroughItsStylusTipAgainstAPlan) {
  RP_REQUIRE_SHARED_DATA(PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha");
  const std::string sequence = PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha";
  const std::string config = PlusData + "/ConfigFiles/PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml";
  rp::ExecutionPath path;
  std::string error;
  ASSERT_TRUE(rp::ReadExecutionPath(sequence, {"StylusTipToReference", config}, path, error)) << error;
  EXPECT_EQ(path.Kind, "plus-sequence");
  EXPECT_EQ(path.Samples, 1000u);

  // Independently: tip = (ReferenceToTracker)^-1 · StylusToTracker · StylusTipToStylus (the
  // configuration's calibration, typed in from the file).
  Eigen::Matrix4d tipToStylus;
  tipToStylus << 0.997175, -0.0713837, -0.0233796, 108.565, 0.0714032, 0.997448, 0, 7.77385, 0.0233199, -0.00166938,
      0.999727, 2.5389, 0, 0, 0, 1;
  const auto stylus = RawTransforms(sequence, "StylusToTracker");
  const auto reference = RawTransforms(sequence, "ReferenceToTracker");
  std::vector<Vec3> expected;
  for (const auto& [frame, s] : stylus) {
    const auto r = reference.find(frame);
    if (r == reference.end()) continue;
    const Eigen::Vector4d p = r->second.inverse() * s * tipToStylus * Eigen::Vector4d(0, 0, 0, 1);
    expected.push_back({p.x(), p.y(), p.z()});
  }
  ASSERT_EQ(path.Points.size(), expected.size());
  EXPECT_EQ(path.Skipped, 1000u - expected.size());
  for (size_t i = 0; i < expected.size(); ++i) ASSERT_LT(rp::Norm(path.Points[i] - expected[i]), 1e-6) << i;

  // The plan, in Reference coordinates: from near the stylus's third rest (on the phantom's top
  // landmarks) to near its fifth (138 mm below, on the bottom ones).
  rp::ExecutionInput input;
  input.Plan = Axis({2.0, 3.0, 130.0}, {8.0, 6.0, -8.0});
  input.PlanDiameterMm = 2;
  input.Path = path.Points;
  rp::ExecutionScore score;
  ASSERT_TRUE(rp::ScoreExecution(input, score, error)) << error;
  // The same figures from Eigen: the path resampled every 0.1 mm here, its principal axis by SVD.
  std::vector<Eigen::Vector3d> resampled{{expected[0].x, expected[0].y, expected[0].z}};
  double since = 0;
  for (size_t i = 1; i < expected.size(); ++i) {
    const Eigen::Vector3d a(expected[i - 1].x, expected[i - 1].y, expected[i - 1].z), b(expected[i].x, expected[i].y, expected[i].z);
    const double length = (b - a).norm();
    double at = 0.1 - since, lastAt = -since;  // distances into this segment
    for (; at <= length; at += 0.1) {
      resampled.push_back(a + (b - a) * (at / length));
      lastAt = at;
    }
    since = length - lastAt;
  }
  if ((resampled.back() - Eigen::Vector3d(expected.back().x, expected.back().y, expected.back().z)).norm() > 1e-12)
    resampled.emplace_back(expected.back().x, expected.back().y, expected.back().z);  // the last point kept
  Eigen::MatrixXd centred(resampled.size(), 3);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : resampled) mean += p;
  mean /= double(resampled.size());
  for (size_t i = 0; i < resampled.size(); ++i) centred.row(Eigen::Index(i)) = (resampled[i] - mean).transpose();
  Eigen::Vector3d u = Eigen::JacobiSVD<Eigen::MatrixXd>(centred, Eigen::ComputeThinV).matrixV().col(0);
  const Eigen::Vector3d first(expected.front().x, expected.front().y, expected.front().z),
      last(expected.back().x, expected.back().y, expected.back().z);
  if (u.dot(last - first) < 0) u = -u;
  const Eigen::Vector3d entry(input.Plan.Entry().x, input.Plan.Entry().y, input.Plan.Entry().z);
  const Eigen::Vector3d target(input.Plan.Target().x, input.Plan.Target().y, input.Plan.Target().z);
  const Eigen::Vector3d n = (target - entry).normalized();
  auto cross = [&](const Eigen::Vector3d& at) { return mean + u * ((at - mean).dot(n) / u.dot(n)); };
  EXPECT_NEAR(score.EntryOffsetMm, (cross(entry) - entry).norm(), 1e-6);
  EXPECT_NEAR(score.TipOffsetMm, (cross(target) - target).norm(), 1e-6);
  EXPECT_NEAR(score.AngleDeg, std::acos(std::clamp(u.dot(n), -1.0, 1.0)) * 180 / M_PI, 1e-6);
  double deepest = -1e300;
  for (const auto& p : expected) deepest = std::max(deepest, (Eigen::Vector3d(p.x, p.y, p.z) - entry).dot(n));
  EXPECT_NEAR(score.DepthErrorMm, deepest - (target - entry).norm(), 1e-6);
}

// The navigation logic reads a moving tool out against the chosen trajectory on every move: a tip
// 3, 4 mm off a plan running down −S, pointing along it, is 5 mm off at the entry and laterally,
// 0°, and 40 mm short of a target 50 mm deep; tilted 30° about A its axis crosses the entry plane
// 10·tan 30° farther along R.
TEST(NavigationLogic, ReadsTheToolOutAgainstThePlannedTrajectoryWhenItMoves) {
  const double entry[3] = {0, 0, 0}, target[3] = {0, 0, -50};
  rptest::PlannedToolScene s(entry, target);
  vtkRPLinearTransformNode* tip = s.Tip;
  vtkRPNavigationLogic* logic = s.Logic;
  const double shifted[16] = {1, 0, 0, 3, 0, 1, 0, 4, 0, 0, 1, -10, 0, 0, 0, 1};
  const rp::GuidanceReadout& r = s.Place(shifted);
  ASSERT_TRUE(r.Valid);
  EXPECT_NEAR(r.EntryErrorMm, 5, 1e-9);
  EXPECT_NEAR(r.LateralMm, 5, 1e-9);
  EXPECT_NEAR(r.AngleDeg, 0, 1e-9);
  EXPECT_NEAR(r.DepthToTargetMm, 40, 1e-9);
  EXPECT_EQ(tip->GetAttribute("Navigation.Guidance"), rp::ReadoutString(r));
  // Tilted 30° about A (the tool's −z leans towards −R at depth): back along the tool's axis to S = 0.
  const double c = std::cos(M_PI / 6), sn = std::sin(M_PI / 6);
  const double tilted[16] = {c, 0, sn, 0, 0, 1, 0, 0, -sn, 0, c, -10, 0, 0, 0, 1};
  tip->SetMatrixTransformToParent(tilted);
  EXPECT_NEAR(logic->GetLastReadout().AngleDeg, 30, 1e-9);
  EXPECT_NEAR(logic->GetLastReadout().EntryErrorMm, 10 * std::tan(M_PI / 6), 1e-9);
  logic->SetTrajectoryNodeID("");
  logic->Update();
  EXPECT_FALSE(logic->GetLastReadout().Valid);
  EXPECT_EQ(tip->GetAttribute("Navigation.Guidance"), "");
}

// The read-out's closest structure at risk is the scene's (a protected model, as the Planning logic
// finds it), from the tool's surface (the trajectory's tool radius): a sphere of radius R meshed by
// vtkSphereSource has a vertex at its pole and every other point inside the sphere, so from a tip on
// the pole's axis at D from the centre the mesh is exactly D − R away; under the margin it warns.
TEST(NavigationLogic, TheClosestStructureAtRiskOfTheSceneFromTheToolsSurface) {
  const double entry[3] = {0, 0, 0}, target[3] = {0, 0, -50};
  rptest::PlannedToolScene s(entry, target);
  s.Trajectory->SetToolDiameterMm(2);
  vtkRPScene* scene = s.Scene;
  const double radius = 5, center[3] = {20, 0, -10}, margin = 3;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(center[0], center[1], center[2]);
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(48);
  sphere->SetPhiResolution(48);
  sphere->Update();
  vtkNew<vtkRPModelNode> vessel;
  vessel->SetName("vessel");
  vessel->SetPolyData(sphere->GetOutput());
  scene->AddNode(vessel);
  vtkNew<vtkRPModelNode> bone;  // not protected: not a structure at risk, however close
  bone->SetName("bone");
  vtkNew<vtkSphereSource> near;
  near->SetCenter(center[0], center[1] + 3, center[2] + radius + 5);  // 2.5 mm from the first tip
  near->Update();
  bone->SetPolyData(near->GetOutput());
  scene->AddNode(bone);
  auto place = [&](double d) {
    const double m[16] = {1, 0, 0, center[0], 0, 1, 0, center[1], 0, 0, 1, center[2] + d, 0, 0, 0, 1};
    return s.Place(m);
  };
  EXPECT_FALSE(place(radius + 5).HasStructure) << "nothing is protected yet";
  vessel->SetProtection({true, margin});
  s.Logic->Update();  // the tool did not move: what the panel's display-rate timer does
  rp::GuidanceReadout r = s.Logic->GetLastReadout();
  ASSERT_TRUE(r.Valid);
  ASSERT_TRUE(r.HasStructure) << s.Logic->GetStructuresProblem();
  EXPECT_EQ(r.ClosestStructure, "vessel");
  EXPECT_NEAR(r.ClosestStructureMm, 5 - 1, 1e-9);  // D − R − the tool's radius
  EXPECT_FALSE(r.WithinMargin);
  r = place(radius + 3.5);
  EXPECT_NEAR(r.ClosestStructureMm, 3.5 - 1, 1e-9);
  EXPECT_TRUE(r.WithinMargin);
  const std::string line = s.Tip->GetAttribute("Navigation.Guidance");
  EXPECT_NE(line.find("closestStructure=vessel;closestStructureMm=2.500;withinMargin=1"), std::string::npos) << line;
  r = place(-radius / 2);  // inside it: negative
  EXPECT_NEAR(r.ClosestStructureMm, -radius / 2 - 1, 0.05);
}

// `roboplan score` on a plan file and a CSV path it has never seen: a line offset 1 mm from the
// planned entry and tilted 2° gives, in closed form, entry offset 1, tip offset 1 + L·tan 2°,
// angle 2°, depth error (its length along the plan) − L, largest deviation at its deepest point.
TEST(ScoreCommand, ACsvPathOffsetAndTiltedGivesTheClosedFormsInJson) {
  const double length = 40, theta = 2 * M_PI / 180, run = 42;
  vtkNew<vtkRPTrajectoryNode> trajectory;
  const double entry[3] = {10, 20, 30}, target[3] = {10, 20, 30 - length};
  trajectory->SetEntryAndTarget(entry, target);
  trajectory->SetToolDiameterMm(3);
  trajectory->SetName("tunnel");
  const std::string plan = (std::filesystem::temp_directory_path() / "rpGuidanceTest-plan.mrk.json").string();
  std::string error;
  const rp::NodeStorage* storage = rp::FindNodeStorageForFile(plan);
  ASSERT_TRUE(storage && storage->Write(trajectory, plan, error)) << error;
  const std::string path = TiltedPath("tilted.csv", theta, run);
  const std::string table = (std::filesystem::temp_directory_path() / "rpGuidanceTest-deviation.csv").string();
  std::ostringstream out, err;
  ASSERT_EQ(rp::RunScoreCommand({"--plan", plan, "--path", path, "--csv", table, "--json"}, out, err), 0) << err.str();
  const nlohmann::json doc = nlohmann::json::parse(out.str());
  EXPECT_NEAR(doc["entryOffsetMm"].get<double>(), 1, 1e-6);
  EXPECT_NEAR(doc["tipOffsetMm"].get<double>(), 1 + length * std::tan(theta), 1e-6);
  EXPECT_NEAR(doc["angleDeg"].get<double>(), 2, 1e-6);
  EXPECT_NEAR(doc["depthErrorMm"].get<double>(), run * std::cos(theta) - length, 1e-6);
  EXPECT_NEAR(doc["maxDeviationMm"].get<double>(), 1 + run * std::sin(theta), 1e-6);
  EXPECT_EQ(doc["path"]["kind"], "csv");
  EXPECT_TRUE(doc["outsideVolumeMm3"].is_null());  // a tip (no radius): no swept volume
  EXPECT_TRUE(std::filesystem::exists(table));

  // With a tool radius the swept volume is measured; bad input names the file and the problem.
  out.str("");
  ASSERT_EQ(rp::RunScoreCommand({"--plan", plan, "--path", path, "--tool-radius", "1.5", "--json"}, out, err), 0) << err.str();
  EXPECT_GT(nlohmann::json::parse(out.str())["outsideVolumeMm3"].get<double>(), 0);
  std::ostringstream err2;
  EXPECT_EQ(rp::RunScoreCommand({"--plan", plan, "--path", "/nonexistent/path.csv"}, out, err2), 1);
  EXPECT_NE(err2.str().find("/nonexistent/path.csv"), std::string::npos) << err2.str();
  std::ostringstream err3;
  EXPECT_EQ(rp::RunScoreCommand({"--plan", path, "--path", path}, out, err3), 1);
  EXPECT_NE(err3.str().find("--plan"), std::string::npos) << err3.str();
  std::ostringstream err4;
  EXPECT_EQ(rp::RunScoreCommand({"--plan", plan}, out, err4), 2);
}

// The Navigation logic scores an execution against a trajectory of the scene (what `roboplan score`
// and the panel call): the figures the command prints for the same plan and path; the bone is a
// model of the scene in world RAS (its parent transform followed: a ball under a transform scores
// as the same ball moved there); bad input named, the scene unchanged.
TEST(ScoreLogic, ScoresATrajectoryOfTheSceneAsTheCommandDoes) {
  const double length = 40, theta = 2 * M_PI / 180, run = 42;
  const double entry[3] = {10, 20, 30}, target[3] = {10, 20, 30 - length};
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrajectoryNode> trajectory;
  trajectory->SetEntryAndTarget(entry, target);
  trajectory->SetToolDiameterMm(3);
  trajectory->SetName("tunnel");
  scene->AddNode(trajectory);
  const std::string path = TiltedPath("logic.csv", theta, run);
  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  rp::ScoreRequest request;
  request.PathFile = path;
  rp::ScoredExecution scored;
  std::string error;
  ASSERT_TRUE(logic->ScoreExecution(request, scored, error)) << error;
  EXPECT_NEAR(scored.Score.EntryOffsetMm, 1, 1e-9);
  EXPECT_NEAR(scored.Score.TipOffsetMm, 1 + length * std::tan(theta), 1e-9);
  EXPECT_NEAR(scored.Score.AngleDeg, 2, 1e-9);
  EXPECT_TRUE(scored.Warnings.empty());
  EXPECT_FALSE(scored.Score.HasBreach);

  // Named as the node (a Slicer markups file loads as a node named after the file).
  const auto planDir = std::filesystem::temp_directory_path() / "rpGuidanceTest-logic";
  std::filesystem::create_directories(planDir);
  const std::string plan = (planDir / "tunnel.mrk.json").string();
  const rp::NodeStorage* storage = rp::FindNodeStorageForFile(plan);
  ASSERT_TRUE(storage && storage->Write(trajectory, plan, error)) << error;
  std::ostringstream out, err;
  ASSERT_EQ(rp::RunScoreCommand({"--plan", plan, "--path", path, "--json"}, out, err), 0) << err.str();
  nlohmann::json command = nlohmann::json::parse(out.str()), logicJson = nlohmann::json::parse(rp::ScoredExecutionJson(scored, plan));
  EXPECT_EQ(logicJson, command);

  // The bone: a ball of radius 30 about the plan's middle, once built there and once built at the
  // origin under a transform that moves it there: the same breach figures.
  auto ball = [&](const double center[3]) {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(center[0], center[1], center[2]);
    sphere->SetRadius(30);
    sphere->SetThetaResolution(32);
    sphere->SetPhiResolution(32);
    sphere->Update();
    vtkSmartPointer<vtkRPModelNode> model = vtkSmartPointer<vtkRPModelNode>::New();
    model->SetPolyData(sphere->GetOutput());
    scene->AddNode(model);
    return model;
  };
  const double middle[3] = {10, 20, 10}, origin[3] = {0, 0, 0};
  vtkSmartPointer<vtkRPModelNode> placed = ball(middle), moved = ball(origin);
  vtkNew<vtkRPLinearTransformNode> move;
  vtkNew<vtkMatrix4x4> m;
  for (int i = 0; i < 3; ++i) m->SetElement(i, 3, middle[i]);
  move->SetMatrixTransformToParent(m);
  scene->AddNode(move);
  moved->SetAndObserveTransformNodeID(move->GetID());
  rp::ScoredExecution a, b;
  request.BoneModelNodeID = placed->GetID();
  ASSERT_TRUE(logic->ScoreExecution(request, a, error)) << error;
  request.BoneModelNodeID = moved->GetID();
  ASSERT_TRUE(logic->ScoreExecution(request, b, error)) << error;
  ASSERT_TRUE(a.Score.HasBreach && b.Score.HasBreach);
  EXPECT_NEAR(a.Score.BreachMm, b.Score.BreachMm, 1e-9);
  EXPECT_NEAR(a.Score.BreachDepthMm, b.Score.BreachDepthMm, 1e-9);

  // Bad input: named; the scene keeps its nodes.
  const int nodes = scene->GetNumberOfNodes();
  request.BoneModelNodeID = "vtkRPModelNode404";
  EXPECT_FALSE(logic->ScoreExecution(request, a, error));
  EXPECT_NE(error.find("no model 'vtkRPModelNode404'"), std::string::npos) << error;
  request.BoneModelNodeID.clear();
  request.Trajectory = "screw";
  EXPECT_FALSE(logic->ScoreExecution(request, a, error));
  EXPECT_NE(error.find("no trajectory 'screw' (it has: 'tunnel')"), std::string::npos) << error;
  request.Trajectory.clear();
  request.PathFile = TempFile("logic-one.csv", "R,A,S\n1,2,3\n");
  EXPECT_FALSE(logic->ScoreExecution(request, a, error));
  EXPECT_NE(error.find("fewer than two distinct points"), std::string::npos) << error;
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
}

}  // namespace
