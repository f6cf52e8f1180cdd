// The registration logic in the scene (lists in, TrackerToRAS out, recompute on point moves,
// attributes) and the `roboplan register` command on Slicer files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

#include "rpMarkupsIO.h"
#include "rpModelIO.h"
#include "rpRegisterCommand.h"
#include "rpTransformIO.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLandmarkRegistrationLogic.h"
#include "vtkRPLinearTransformNode.h"

namespace {

std::string OutputDir() {
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR);
  std::filesystem::create_directories(dir);
  return dir;
}

// TrackerToRAS: 30° about (1,1,0) then (12,-40,85).
Eigen::Matrix4d TrackerToRAS() {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(12, -40, 85);
  return m;
}

const double LandmarksRAS[5][3] = {{40, 10, 0}, {-35, 20, 5}, {5, -45, 10}, {0, 5, 50}, {20, 30, -30}};

void FillLists(vtkRPFiducialListNode* tracker, vtkRPFiducialListNode* image, int n = 5) {
  const Eigen::Matrix4d inverse = TrackerToRAS().inverse();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector4d ras(LandmarksRAS[i][0], LandmarksRAS[i][1], LandmarksRAS[i][2], 1);
    const Eigen::Vector4d t = inverse * ras;
    const double trackerPoint[3] = {t[0], t[1], t[2]};
    tracker->AddControlPoint(trackerPoint, "L" + std::to_string(i + 1));
    image->AddControlPoint(LandmarksRAS[i], "L" + std::to_string(i + 1));
  }
}

void ExpectMatrix(const vtkMatrix4x4* m, const Eigen::Matrix4d& expected, double tolerance) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(m->GetElement(i, j), expected(i, j), tolerance) << i << "," << j;
}

TEST(LandmarkRegistrationLogic, RegistersAndRecomputesWhenAPointMoves) {
  vtkNew<vtkRPFiducialListNode> tracker, image;
  FillLists(tracker, image);
  vtkNew<vtkRPLinearTransformNode> output;
  output->SetName("TrackerToRAS");
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  logic->SetFREThreshold(1.0);
  logic->SetFLE(0.25);
  logic->SetFromFiducials(tracker);
  logic->SetToFiducials(image);
  logic->SetOutputTransform(output);  // auto update: registers now
  ExpectMatrix(output->GetMatrixTransformToParent(), TrackerToRAS(), 1e-9);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "accepted");
  EXPECT_EQ(output->GetAttribute("Registration.Mode"), "rigid");
  EXPECT_EQ(output->GetAttribute("Registration.NumberOfPairs"), "5");
  EXPECT_LT(std::stod(output->GetAttribute("Registration.FRE")), 1e-9);
  EXPECT_NEAR(std::stod(output->GetAttribute("Registration.ExpectedFRE")), 0.25 * std::sqrt(1 - 2.0 / 5), 1e-6);
  EXPECT_GT(std::stod(output->GetAttribute("Registration.PredictedTRE")), 0.0);
  std::istringstream residuals(output->GetAttribute("Registration.Residuals"));
  int count = 0;
  for (double r; residuals >> r; ++count) EXPECT_LT(r, 1e-9);
  EXPECT_EQ(count, 5);

  // Move one image point by 0.3 mm: recomputed once, FRE now > 0 and still accepted.
  const int before = logic->GetNumberOfUpdates();
  double p[3];
  image->GetNthControlPointPosition(2, p);
  p[2] += 0.3;
  image->SetNthControlPointPosition(2, p);
  EXPECT_EQ(logic->GetNumberOfUpdates(), before + 1);
  const double fre = std::stod(output->GetAttribute("Registration.FRE"));
  EXPECT_GT(fre, 0.05);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "accepted");

  // Drag it 10 mm away: rejected, the matrix keeps the last accepted registration.
  vtkNew<vtkMatrix4x4> lastGood;
  lastGood->DeepCopy(output->GetMatrixTransformToParent());
  p[2] += 10;
  image->SetNthControlPointPosition(2, p);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "rejected");
  EXPECT_NE(output->GetAttribute("Registration.Reason").find("exceeds the threshold"), std::string::npos);
  EXPECT_EQ(output->GetAttribute("Registration.Suspects"), "3");
  EXPECT_FALSE(output->GetAttribute("Registration.Warnings").empty());
  for (int i = 0; i < 16; ++i)
    EXPECT_EQ(output->GetMatrixTransformToParent()->GetElement(i / 4, i % 4), lastGood->GetElement(i / 4, i % 4));

  // Unselect that pair: left out, exact again (4 pairs).
  image->SetNthControlPointSelected(2, false);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "accepted");
  EXPECT_EQ(output->GetAttribute("Registration.NumberOfPairs"), "4");
  ExpectMatrix(output->GetMatrixTransformToParent(), TrackerToRAS(), 1e-9);

  // A batch of moves recomputes once.
  const int beforeBatch = logic->GetNumberOfUpdates();
  const int previous = tracker->StartModify();
  for (int i = 0; i < 5; ++i) {
    tracker->GetNthControlPointPosition(i, p);
    p[0] += 1;
    tracker->SetNthControlPointPosition(i, p);
  }
  tracker->EndModify(previous);
  EXPECT_EQ(logic->GetNumberOfUpdates(), beforeBatch + 1);
  EXPECT_NEAR(output->GetMatrixTransformToParent()->GetElement(0, 3),
              (TrackerToRAS() * Eigen::Vector4d(-1, 0, 0, 1))[0], 1e-9);

  // Too few pairs: refused with the reason.
  image->RemoveNthControlPoint(4);
  EXPECT_EQ(output->GetAttribute("Registration.Status"), "rejected");
  EXPECT_NE(output->GetAttribute("Registration.Reason").find("unequal numbers"), std::string::npos);
}

TEST(LandmarkRegistrationLogic, PredictedTREMapOnAModel) {
  vtkNew<vtkRPFiducialListNode> tracker, image;
  FillLists(tracker, image);
  vtkNew<vtkRPLinearTransformNode> output;
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  logic->SetFLE(0.25);
  logic->SetFromFiducials(tracker);
  logic->SetToFiducials(image);
  logic->SetOutputTransform(output);
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(100);
  sphere->Update();
  const double largest = logic->UpdatePredictedTREMap(sphere->GetOutput());
  ASSERT_NE(sphere->GetOutput()->GetPointData()->GetArray("PredictedTRE"), nullptr);
  EXPECT_GT(largest, 0.25 / std::sqrt(5.0));  // above the TRE at the centroid, FLE/sqrt(N)
}

// An ellipsoid "bone" in RAS and every 7th of its vertices as points digitized in tracker space.
void MakeBone(vtkPolyData* bone, vtkRPFiducialListNode* surface) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(60);
  sphere->SetPhiResolution(40);
  sphere->SetRadius(1);
  sphere->Update();
  bone->DeepCopy(sphere->GetOutput());
  for (vtkIdType i = 0; i < bone->GetNumberOfPoints(); ++i) {
    double p[3];
    bone->GetPoint(i, p);
    bone->GetPoints()->SetPoint(i, 55 * p[0] + 5, 35 * p[1] - 3, 25 * p[2] + 8);
  }
  const Eigen::Matrix4d inverse = TrackerToRAS().inverse();
  for (vtkIdType i = 0; i < bone->GetNumberOfPoints(); i += 7) {
    double p[3];
    bone->GetPoint(i, p);
    const Eigen::Vector4d t = inverse * Eigen::Vector4d(p[0], p[1], p[2], 1);
    const double q[3] = {t[0], t[1], t[2]};
    surface->AddControlPoint(q);
  }
}

TEST(LandmarkRegistrationLogic, SurfaceICPRefinesTheLandmarkResult) {
  // Landmarks with 1 mm errors give a rough TrackerToRAS; 300 points digitized on an ellipsoid
  // "bone" (exact, in tracker coordinates) refine it to the truth.
  vtkNew<vtkRPFiducialListNode> tracker, image, surface;
  FillLists(tracker, image);
  const double shifts[5][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 1, -1}};
  for (int i = 0; i < 5; ++i) {
    double p[3];
    image->GetNthControlPointPosition(i, p);
    for (int k = 0; k < 3; ++k) p[k] += shifts[i][k];
    image->SetNthControlPointPosition(i, p);
  }
  vtkNew<vtkPolyData> bone;
  MakeBone(bone, surface);
  vtkNew<vtkRPLinearTransformNode> output;
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  logic->SetFromFiducials(tracker);
  logic->SetToFiducials(image);
  logic->SetOutputTransform(output);
  ASSERT_EQ(output->GetAttribute("Registration.Status"), "accepted");
  EXPECT_GT(std::stod(output->GetAttribute("Registration.FRE")), 0.3);
  rp::SurfaceICPOptions options;
  options.InlierFraction = 1.0;
  ASSERT_TRUE(logic->RefineWithSurfaceICP(surface, bone, options)) << logic->GetLastICPResult().Error;
  ExpectMatrix(output->GetMatrixTransformToParent(), TrackerToRAS(), 1e-3);
  EXPECT_EQ(output->GetAttribute("Registration.Method"), "landmarks+ICP");
  EXPECT_LT(std::stod(output->GetAttribute("Registration.ICP.InlierRMS")), 1e-3);
  // A landmark moves: the landmark result replaces the refined one.
  double p[3];
  image->GetNthControlPointPosition(0, p);
  p[0] += 0.1;
  image->SetNthControlPointPosition(0, p);
  EXPECT_EQ(output->GetAttribute("Registration.Method"), "landmarks");
  EXPECT_FALSE(output->HasAttribute("Registration.ICP.InlierRMS"));
}

std::string WriteLists(const std::string& name, bool fcsv, bool moveOnePoint) {
  vtkNew<vtkRPFiducialListNode> tracker, image;
  FillLists(tracker, image);
  if (moveOnePoint) {
    double p[3];
    image->GetNthControlPointPosition(1, p);
    p[0] += 12;
    image->SetNthControlPointPosition(1, p);
  }
  const std::string base = OutputDir() + "/" + name;
  std::string error;
  if (fcsv) {
    EXPECT_TRUE(rp::WriteFcsv(base + "_tracker.fcsv", tracker, error)) << error;
    EXPECT_TRUE(rp::WriteFcsv(base + "_image.fcsv", image, error)) << error;
  } else {
    EXPECT_TRUE(rp::WriteMarkupsJson(base + "_tracker.mrk.json", tracker, error)) << error;
    EXPECT_TRUE(rp::WriteMarkupsJson(base + "_image.mrk.json", image, error)) << error;
  }
  return base;
}

int RunCommand(const std::vector<std::string>& args, std::string& out, std::string& err) {
  std::ostringstream o, e;
  const int code = rp::RunRegisterCommand(args, o, e);
  out = o.str();
  err = e.str();
  return code;
}

TEST(RegisterCommand, WritesTheTransformSlicerReads) {
  for (bool fcsv : {false, true}) {
    const std::string base = WriteLists(fcsv ? "cli_fcsv" : "cli_json", fcsv, false);
    const std::string ext = fcsv ? ".fcsv" : ".mrk.json";
    const std::string outPath = base + "_TrackerToRAS.tfm";
    std::filesystem::remove(outPath);
    std::string out, err;
    ASSERT_EQ(RunCommand({base + "_tracker" + ext, base + "_image" + ext, "--out", outPath, "--target", "0,0,20"}, out, err),
              0)
        << err;
    EXPECT_NE(out.find("predicted TRE at the target"), std::string::npos) << out;
    vtkNew<vtkMatrix4x4> m;
    std::string error;
    ASSERT_TRUE(rp::ReadTransformFile(outPath, m, error)) << error;
    ExpectMatrix(m, TrackerToRAS(), 1e-9);
  }
}

TEST(RegisterCommand, RejectsWithoutWritingAndReportsJson) {
  const std::string base = WriteLists("cli_bad", false, true);
  const std::string outPath = base + "_TrackerToRAS.tfm";
  std::filesystem::remove(outPath);
  std::string out, err;
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", outPath, "--fre-threshold", "1.5",
                 "--json"},
                out, err),
            1);
  EXPECT_FALSE(std::filesystem::exists(outPath));
  EXPECT_NE(err.find("exceeds the threshold 1.500 mm"), std::string::npos) << err;
  const auto doc = nlohmann::json::parse(out);
  EXPECT_EQ(doc["accepted"], false);
  EXPECT_EQ(doc["pairs"], 5);
  EXPECT_GT(doc["fre"].get<double>(), 1.5);
  EXPECT_TRUE(doc["out"].is_null());
  ASSERT_EQ(doc["fiducials"].size(), 5u);
  EXPECT_EQ(doc["fiducials"][1]["label"], "L2");
  ASSERT_EQ(doc["suspects"].size(), 1u);
  EXPECT_EQ(doc["suspects"][0]["index"], 1);

  // Without a threshold the same data is accepted (with warnings) and written.
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", outPath, "--fre-threshold", "0",
                 "--json"},
                out, err),
            0)
      << err;
  EXPECT_TRUE(std::filesystem::exists(outPath));
  EXPECT_FALSE(nlohmann::json::parse(out)["warnings"].empty());
}

TEST(RegisterCommand, SurfaceICPRefinement) {
  // Landmarks off by 1 mm; the bone surface (written as Slicer would, LPS .vtp) fixes it.
  vtkNew<vtkRPFiducialListNode> tracker, image, surface;
  FillLists(tracker, image);
  double p[3];
  image->GetNthControlPointPosition(0, p);
  p[1] += 1.5;
  image->SetNthControlPointPosition(0, p);
  vtkNew<vtkPolyData> bone;
  MakeBone(bone, surface);
  const std::string base = OutputDir() + "/cli_icp";
  std::string error;
  ASSERT_TRUE(rp::WriteMarkupsJson(base + "_tracker.mrk.json", tracker, error)) << error;
  ASSERT_TRUE(rp::WriteMarkupsJson(base + "_image.mrk.json", image, error)) << error;
  ASSERT_TRUE(rp::WriteFcsv(base + "_surface.fcsv", surface, error)) << error;
  ASSERT_TRUE(rp::WriteModelFile(base + "_bone.vtp", bone, error)) << error;
  std::string out, err;
  ASSERT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", base + ".h5", "--icp-points",
                        base + "_surface.fcsv", "--icp-model", base + "_bone.vtp", "--icp-inliers", "1", "--json"},
                       out, err),
            0)
      << err;
  const auto doc = nlohmann::json::parse(out);
  EXPECT_EQ(doc["icp"]["ok"], true);
  EXPECT_LT(doc["icp"]["inlierRmsMM"].get<double>(), 1e-3);
  EXPECT_GT(doc["fre"].get<double>(), 0.3);  // the landmark fit is reported as it was
  vtkNew<vtkMatrix4x4> m;
  ASSERT_TRUE(rp::ReadTransformFile(base + ".h5", m, error)) << error;
  ExpectMatrix(m, TrackerToRAS(), 1e-3);
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", base + ".tfm", "--icp-points",
                        base + "_surface.fcsv"},
                       out, err),
            2);
}

TEST(RegisterCommand, BadArgumentsAndFiles) {
  const std::string base = WriteLists("cli_args", false, false);
  std::string out, err;
  EXPECT_EQ(RunCommand({"--help"}, out, err), 0);
  EXPECT_NE(out.find("does NOT write --out"), std::string::npos);
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json"}, out, err), 2);
  EXPECT_NE(err.find("--out"), std::string::npos);
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", "x.tfm", "--mode", "affine"}, out, err),
            2);
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", base + "_image.mrk.json", "--out", "x.tfm", "--target", "1,2"}, out, err),
            2);
  EXPECT_EQ(RunCommand({base + "_missing.mrk.json", base + "_image.mrk.json", "--out", "x.tfm"}, out, err), 1);
  EXPECT_NE(err.find("_missing.mrk.json"), std::string::npos) << err;
  EXPECT_EQ(RunCommand({base + "_tracker.mrk.json", OutputDir() + "/x.nrrd", "--out", "x.tfm"}, out, err), 1);
  EXPECT_NE(err.find("not a fiducial file"), std::string::npos) << err;
}

}  // namespace
