// `roboplan plan`: the figures and the interface names other tools script (lengthMm,
// lengthInBoneMm, profile, breach, clearance; best, seconds), the plan written as a Slicer line,
// and every bad input named with exit 1 (nothing written): a zero-length trajectory, an entry
// inside a structure at risk, a target outside the volume, a plane of zero normal, a screw longer
// than the bone, a plan of another patient's CT.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSphereSource.h>

#include "rpModelIO.h"
#include "rpNodeStorage.h"
#include "rpPlanCommand.h"
#include "rpTestOutput.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"

namespace fs = std::filesystem;

namespace {

struct PlanRun {
  int Code = 0;
  std::string Out, Err;
  nlohmann::json Json() const { return nlohmann::json::parse(this->Out); }
};

PlanRun Plan(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  PlanRun r;
  r.Code = rp::RunPlanCommand(args, out, err);
  r.Out = out.str(), r.Err = err.str();
  return r;
}

// A CT of 1 mm voxels over RAS [-30, 30]^3 (shifted by `shift` along R): a block of bone
// (1000 HU) over [-10, 10] x [-10, 10] x [-20, 20], -1000 HU around it.
std::string WriteBlockCT(const fs::path& dir, const std::string& name, double shift = 0) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(61, 61, 61);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < 61; ++k)
    for (int j = 0; j < 61; ++j)
      for (int i = 0; i < 61; ++i) {
        const double x = i - 30, y = j - 30, z = k - 30;
        *v++ = std::fabs(x) <= 10 && std::fabs(y) <= 10 && std::fabs(z) <= 20 ? 1000 : -1000;
      }
  vtkNew<vtkRPScalarVolumeNode> ct;
  ct->SetImageData(image);
  const double spacing[3] = {1, 1, 1}, origin[3] = {-30 + shift, -30, -30}, directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ct->SetGeometry(spacing, origin, directions);
  const std::string path = (dir / name).string();
  std::string error;
  EXPECT_TRUE(rp::SaveDataFile(ct, path, error)) << error;
  return path;
}

std::string WriteSphere(const fs::path& dir, const std::string& name, const double center[3], double radius) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(const_cast<double*>(center));
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(32);
  sphere->Update();
  const std::string path = (dir / name).string();
  std::string error;
  EXPECT_TRUE(rp::WriteModelFile(path, sphere->GetOutput(), error)) << error;
  return path;
}

}  // namespace

TEST(PlanCommand, ATrajectoryPrintsItsFiguresWithTheInterfacesNamesAndWritesASlicerLine) {
  const fs::path dir = rptest::TestDir("trajectory");
  const std::string ct = WriteBlockCT(dir, "ct.nrrd");
  const double vessel[3] = {20, 0, 0};
  const std::string vessels = WriteSphere(dir, "vessels.vtp", vessel, 4);
  const std::string plan = (dir / "tunnel.mrk.json").string(), chart = (dir / "profile.png").string();
  const PlanRun r = Plan({"trajectory", "--volume", ct, "--entry", "0,0,-25", "--target", "0,0,15", "--diameter", "4",
                      "--protect", vessels + ":3", "--out", plan, "--profile-chart", chart, "--json"});
  ASSERT_EQ(r.Code, 0) << r.Err;
  const nlohmann::json j = r.Json();
  EXPECT_NEAR(j["lengthMm"].get<double>(), 40, 1e-9);
  EXPECT_NEAR(j["lengthInBoneMm"].get<double>(), 35, 0.6);  // the block starts at S = -20: 5 mm outside
  ASSERT_TRUE(j["profile"].is_array());
  EXPECT_EQ(j["profile"][0]["depthMm"].get<double>(), 0);
  EXPECT_TRUE(j["profile"][0].contains("hu"));
  EXPECT_TRUE(j["breach"].is_null());  // 2 mm radius in a 20 mm block
  ASSERT_EQ(j["clearance"].size(), 1u);
  EXPECT_EQ(j["clearance"][0]["name"], "vessels");
  // The axis along S at R = 0 passes 20 mm from the vessel's centre: 20 - 4 - 2, up to its flats.
  EXPECT_NEAR(j["clearance"][0]["clearanceMm"].get<double>(), 14, 0.02);
  EXPECT_NEAR(j["clearance"][0]["depthMm"].get<double>(), 25, 0.5);
  EXPECT_FALSE(j["clearance"][0]["underMargin"].get<bool>());
  EXPECT_TRUE(fs::exists(chart) || r.Err.find("display") != std::string::npos);
  vtkNew<vtkRPScene> scene;
  std::string error;
  auto* back = vtkRPTrajectoryNode::SafeDownCast(rp::LoadDataFile(scene, plan, error));
  ASSERT_NE(back, nullptr) << error;
  EXPECT_EQ(back->GetToolDiameterMm(), 4);
  EXPECT_FALSE(back->GetPlannedOn().empty());
  // The same plan through --plan gives the same figures.
  const PlanRun again = Plan({"trajectory", "--volume", ct, "--plan", plan, "--protect", vessels + ":3", "--json"});
  ASSERT_EQ(again.Code, 0) << again.Err;
  EXPECT_EQ(again.Json()["lengthInBoneMm"], j["lengthInBoneMm"]);
}

TEST(PlanCommand, BadInputIsNamedAndNothingIsWritten) {
  const fs::path dir = rptest::TestDir("bad");
  const std::string ct = WriteBlockCT(dir, "ct.nrrd");
  const double vessel[3] = {0, 0, -25};
  const std::string vessels = WriteSphere(dir, "vessels.vtp", vessel, 3);
  const std::string out = (dir / "never.mrk.json").string();
  const struct {
    std::vector<std::string> args;
    const char* message;
  } cases[] = {
      {{"trajectory", "--volume", ct, "--entry", "1,2,3", "--target", "1,2,3", "--diameter", "2", "--out", out}, "zero length"},
      {{"trajectory", "--volume", ct, "--entry", "0,0,-25", "--target", "0,0,0", "--diameter", "2", "--protect", vessels,
        "--out", out},
       "inside the structure at risk 'vessels'"},
      {{"trajectory", "--volume", ct, "--entry", "0,0,0", "--target", "0,0,80", "--diameter", "2", "--out", out},
       "outside the volume"},
      {{"plane", "--volume", ct, "--origin", "0,0,0", "--normal", "0,0,0", "--out", out}, "normal is zero"},
      {{"screw", "--volume", ct, "--entry", "0,0,-22", "--target", "0,0,15", "--diameter", "3", "--screw-length", "50",
        "--out", out},
       "longer"}};
  for (const auto& c : cases) {
    const PlanRun r = Plan(c.args);
    EXPECT_EQ(r.Code, 1) << c.message << ": " << r.Err;
    EXPECT_NE(r.Err.find(c.message), std::string::npos) << r.Err;
    EXPECT_FALSE(fs::exists(out)) << c.message;
  }
  // A plan made on another patient's CT (another grid) is refused by name.
  const std::string plan = (dir / "other.mrk.json").string();
  ASSERT_EQ(Plan({"trajectory", "--volume", ct, "--entry", "0,0,-5", "--target", "0,0,5", "--diameter", "2", "--out", plan}).Code, 0);
  const std::string otherCT = WriteBlockCT(dir, "other-ct.nrrd", 7.5);
  const PlanRun r = Plan({"trajectory", "--volume", otherCT, "--plan", plan});
  EXPECT_EQ(r.Code, 1);
  EXPECT_NE(r.Err.find("another CT"), std::string::npos) << r.Err;
  // Arguments: an unknown sub-command, a missing value.
  EXPECT_EQ(Plan({"teleport"}).Code, 2);
  EXPECT_EQ(Plan({}).Code, 2);
  EXPECT_EQ(Plan({"trajectory", "--volume", ct, "--entry", "0,0,0"}).Code, 2);
  EXPECT_EQ(Plan({"trajectory", "--help"}).Code, 0);
}

TEST(PlanCommand, ProposeFindsTheEntryFarthestFromTheStructuresAndWritesTheRiskMap) {
  const fs::path dir = rptest::TestDir("propose");
  const std::string ct = WriteBlockCT(dir, "ct.nrrd");
  // Two structures either side of the line R = 0: the best entry on the plane S = -25 is R = 0.
  const double left[3] = {-9, 0, -5}, right[3] = {9, 0, -5};
  const std::string a = WriteSphere(dir, "a.vtp", left, 3), b = WriteSphere(dir, "b.vtp", right, 3);
  const std::string riskMap = (dir / "risk.vtp").string(), best = (dir / "best.mrk.json").string();
  const PlanRun r = Plan({"propose", "--volume", ct, "--target", "0,0,15", "--entry-sphere", "0,0,-25,8", "--diameter", "2",
                      "--protect", a + ":1", "--protect", b + ":1", "--spacing", "0.5", "--risk-map", riskMap, "--out",
                      best, "--json"});
  ASSERT_EQ(r.Code, 0) << r.Err;
  const nlohmann::json j = r.Json();
  ASSERT_GE(j["best"].size(), 1u);
  const auto entry = j["best"][0]["entry"].get<std::vector<double>>();
  EXPECT_NEAR(entry[0], 0, 1.0);
  EXPECT_TRUE(j["seconds"].is_number());
  EXPECT_GT(j["candidates"].get<int>(), 500);
  vtkNew<vtkPolyData> map;
  std::string error;
  ASSERT_TRUE(rp::ReadModelFile(riskMap, map, error)) << error;
  EXPECT_NE(map->GetPointData()->GetArray("clearanceMm"), nullptr);
  vtkNew<vtkRPScene> scene;
  EXPECT_NE(vtkRPTrajectoryNode::SafeDownCast(rp::LoadDataFile(scene, best, error)), nullptr) << error;
}
