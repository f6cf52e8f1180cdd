// The Volumes CLI end to end (phantom → DICOM listing → conversion → registration with a known
// answer) and the scene logic (load, register into a transform node, failures change nothing).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpKneePhantom.h"
#include "rpTransformIO.h"
#include "rpVolumeFiles.h"
#include "rpVolumeRegistration.h"
#include "rpVolumesCommands.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPVolumesLogic.h"

namespace fs = std::filesystem;

namespace {

struct CommandRun {
  int code;
  std::string out, err;
  nlohmann::json Json() const { return nlohmann::json::parse(out); }
};

CommandRun Call(int (*command)(const std::vector<std::string>&, std::ostream&, std::ostream&), std::vector<std::string> args) {
  std::ostringstream out, err;
  const int code = command(args, out, err);
  return {code, out.str(), err.str()};
}

const fs::path& Dir() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(ROBOPLAN_TEST_OUTPUT_DIR);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// The phantom written once for all tests.
const fs::path& PhantomDir() {
  static const fs::path dir = [] {
    const fs::path d = Dir() / "phantom";
    const CommandRun r = Call(rp::RunPhantomCommand, {"--out", d.string(), "--size", "small", "--json"});
    EXPECT_EQ(r.code, 0) << r.err;
    return d;
  }();
  return dir;
}

bool SameVoxels(const rp::ImageVolume& a, const rp::ImageVolume& b) {
  vtkDataArray* sa = a.Image->GetPointData()->GetScalars();
  vtkDataArray* sb = b.Image->GetPointData()->GetScalars();
  if (sa->GetNumberOfTuples() != sb->GetNumberOfTuples()) return false;
  for (vtkIdType i = 0; i < sa->GetNumberOfTuples(); ++i)
    if (sa->GetComponent(i, 0) != sb->GetComponent(i, 0)) return false;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a.IJKToRAS->GetElement(r, c) - b.IJKToRAS->GetElement(r, c)) > 1e-5) return false;
  return true;
}

}  // namespace

TEST(VolumesCommands, PhantomDicomListingAndConversion) {
  const fs::path dir = PhantomDir();
  for (const char* f : {"CT", "MR", "labels.nrrd", "MRToCT-truth.tfm", "phantom.json"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
  const nlohmann::json info = nlohmann::json::parse(std::ifstream(dir / "phantom.json"));
  EXPECT_EQ(info["tissues"].size(), static_cast<size_t>(rp::KneeLabelCount));
  EXPECT_EQ(info["ct"]["dimensions"], nlohmann::json({110, 110, 64}));

  CommandRun r = Call(rp::RunDicomCommand, {dir.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = r.Json();
  ASSERT_EQ(doc["series"].size(), 2u);  // CT and MR, found recursively
  std::set<std::string> modalities;
  for (const auto& s : doc["series"]) {
    modalities.insert(s["modality"].get<std::string>());
    EXPECT_TRUE(s["loadable"].get<bool>()) << s["problem"];
    if (s["modality"] == "MR") {
      EXPECT_NEAR(s["spacing"][2].get<double>(), 1.7, 1e-6);
      EXPECT_EQ(s["size"], nlohmann::json({96, 96, 84}));
    }
  }
  EXPECT_EQ(modalities, (std::set<std::string>{"CT", "MR"}));
  // labels.nrrd, the .tfm, phantom.json and the true surfaces of the real knee.
  EXPECT_EQ(info["surfaces"].size(), 11u);
  EXPECT_EQ(doc["nonDicomFiles"], 3 + info["surfaces"].size());

  // DICOM → NRRD → DICOM → NIfTI: the same voxels and geometry as the generator's CT.
  rp::KneePhantomOptions options;
  options.GenerateMR = false;
  options.GenerateLabels = false;
  rp::KneePhantom phantom;
  std::string error;
  ASSERT_TRUE(rp::GenerateKneePhantom(options, phantom, error));
  ASSERT_EQ(Call(rp::RunConvertCommand, {(dir / "CT").string(), (Dir() / "ct.nrrd").string()}).code, 0);
  ASSERT_EQ(Call(rp::RunConvertCommand, {(Dir() / "ct.nrrd").string(), (Dir() / "ct-dicom").string()}).code, 0);
  r = Call(rp::RunConvertCommand, {(Dir() / "ct-dicom").string(), (Dir() / "ct.nii.gz").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.Json()["dimensions"], nlohmann::json({110, 110, 64}));
  for (const char* name : {"ct.nrrd", "ct-dicom", "ct.nii.gz"}) {
    rp::ImageVolume back;
    ASSERT_TRUE(rp::ReadVolume((Dir() / name).string(), back, error)) << error;
    EXPECT_TRUE(SameVoxels(phantom.CT, back)) << name;
  }

  // Failures: exit 1 with the problem named; bad arguments: exit 2.
  r = Call(rp::RunDicomCommand, {(Dir() / "no-such-folder").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no such file or folder"), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {(dir / "labels.nrrd").string(), (Dir() / "x.nrrd").string(), "--modality", "PET"});
  EXPECT_EQ(r.code, 2);
  r = Call(rp::RunPhantomCommand, {"--out", (Dir() / "p").string(), "--size", "huge"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--size"), std::string::npos);
  r = Call(rp::RunConvertCommand, {(Dir() / "missing.nrrd").string(), (Dir() / "y.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.nrrd"), std::string::npos) << r.err;
}

TEST(VolumesCommands, RegisterVolumesRecoversTheTruth) {
  const fs::path dir = PhantomDir();
  const std::string out = (Dir() / "MRToCT.tfm").string();
  CommandRun r = Call(rp::RunRegisterVolumesCommand, {(dir / "CT").string(), (dir / "MR").string(), "--out", out, "--truth",
                                               (dir / "MRToCT-truth.tfm").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const auto doc = r.Json();
  EXPECT_TRUE(doc["converged"].get<bool>());
  EXPECT_LT(doc["rmsToTruthMM"].get<double>(), 1.0);
  std::printf("[register-volumes] RMS to truth %.3f mm, %.2f s, %d iterations\n", doc["rmsToTruthMM"].get<double>(),
              doc["seconds"].get<double>(), doc["iterations"].get<int>());
  vtkNew<vtkMatrix4x4> written, truth;
  std::string error;
  ASSERT_TRUE(rp::ReadTransformFile(out, written, error)) << error;
  ASSERT_TRUE(rp::ReadTransformFile((dir / "MRToCT-truth.tfm").string(), truth, error)) << error;
  const std::vector<std::array<double, 3>> probe = {{0, 0, 0}, {40, 0, 0}, {0, 40, 0}, {0, 0, 40}};
  EXPECT_LT(rp::TransformRMSDifference(written, truth, probe), 1.0);

  // Not converged: exit 1, the file is not written.
  const std::string out2 = (Dir() / "unconverged.tfm").string();
  r = Call(rp::RunRegisterVolumesCommand,
           {(dir / "CT").string(), (dir / "MR").string(), "--out", out2, "--levels", "4", "--iterations", "2"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out2));
  r = Call(rp::RunRegisterVolumesCommand, {(dir / "CT").string(), (dir / "MR").string(), "--out", out2, "--levels", "0"});
  EXPECT_EQ(r.code, 2);
}

TEST(VolumesLogic, LoadAndRegisterIntoTheScene) {
  const fs::path dir = PhantomDir();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  std::string error;
  vtkRPScalarVolumeNode* ct = logic->LoadVolume((dir / "CT").string(), "CT", error);
  ASSERT_NE(ct, nullptr) << error;
  vtkRPScalarVolumeNode* mr = logic->LoadVolume((dir / "MR").string(), "MR", error);
  ASSERT_NE(mr, nullptr) << error;
  EXPECT_DOUBLE_EQ(ct->GetWindow(), 2000.0);
  const int nodes = scene->GetNumberOfNodes();
  // A failed load changes nothing.
  EXPECT_EQ(logic->LoadVolume((dir / "labels.nrrd.missing").string(), "", error), nullptr);
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
  // Unconverged registration: nothing added, MR not moved.
  rp::RigidRegistrationOptions quick;
  quick.ShrinkFactors = {4};
  quick.SmoothingSigmasMM = {3.0};
  quick.MaxIterationsPerLevel = 2;
  rp::RigidRegistrationResult result;
  EXPECT_EQ(logic->RegisterVolumes(ct, mr, quick, result, error), nullptr);
  EXPECT_NE(error.find("did not converge"), std::string::npos);
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
  EXPECT_TRUE(mr->GetTransformNodeID().empty());

  rp::RigidRegistrationOptions options;  // defaults
  vtkRPLinearTransformNode* transform = logic->RegisterVolumes(ct, mr, options, result, error);
  ASSERT_NE(transform, nullptr) << error;
  EXPECT_EQ(transform->GetName(), "MRToCT");
  EXPECT_EQ(mr->GetTransformNodeID(), transform->GetID());
  vtkNew<vtkMatrix4x4> truth;
  ASSERT_TRUE(rp::ReadTransformFile((dir / "MRToCT-truth.tfm").string(), truth, error)) << error;
  vtkNew<vtkMatrix4x4> mrToWorld;
  mr->GetParentTransformToWorld(mrToWorld);
  // Bone-surface points of the knee, seen in MR coordinates, land where the CT has them.
  std::string loadError;
  const auto model = rp::LoadKneeSurfaceModel(loadError);
  ASSERT_TRUE(model) << loadError;
  const double bounds[6] = {-70, 70, -70, 70, -75, 75};
  const auto femur = model->SurfacePoints(rp::KneeStructure::Femur, 300, bounds);
  vtkNew<vtkMatrix4x4> ctToMR;
  vtkMatrix4x4::Invert(truth, ctToMR);
  std::vector<std::array<double, 3>> inMR;
  for (const auto& p : femur) {
    double q[4] = {p[0], p[1], p[2], 1.0};
    ctToMR->MultiplyPoint(q, q);
    inMR.push_back({q[0], q[1], q[2]});
  }
  EXPECT_LT(rp::TransformRMSDifference(mrToWorld, truth, inMR), 1.0);
}
