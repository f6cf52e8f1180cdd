// ITK transform files with Slicer's convention (LPS, "from parent"), written by hand in ITK's
// text layout and checked against matrices computed by hand:
//   toParentRAS = inverse(S · fromParentLPS · S), S = diag(-1, -1, 1, 1).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkTransform.h>

#include "rpNodeStorage.h"
#include "rpTransformIO.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"

namespace {

std::string OutputDir() {
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/transforms";
  std::filesystem::create_directories(dir);
  return dir;
}

std::string WriteText(const std::string& name, const std::string& text) {
  const std::string path = OutputDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string TfmFile(const std::string& type, const std::string& parameters, const std::string& fixed) {
  return "#Insight Transform File V1.0\n#Transform 0\nTransform: " + type + "\nParameters: " + parameters +
         "\nFixedParameters: " + fixed + "\n";
}

// Row-major 3x4 expected "to parent" RAS matrix.
void ExpectMatrix(const vtkMatrix4x4* m, const std::vector<double>& rows3x4, double tolerance) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(m->GetElement(i, j), rows3x4[static_cast<size_t>(4 * i + j)], tolerance) << i << "," << j;
  EXPECT_EQ(m->GetElement(3, 0), 0.0);
  EXPECT_EQ(m->GetElement(3, 1), 0.0);
  EXPECT_EQ(m->GetElement(3, 2), 0.0);
  EXPECT_EQ(m->GetElement(3, 3), 1.0);
}

TEST(TransformIO, SlicerTranslationFile) {
  // Slicer saves a TrackerToRAS of +10 R, +20 A, -30 S as the LPS resampling transform:
  // fromParentRAS = (-10, -20, +30), in LPS (+10, +20, +30).
  const std::string path = WriteText("translation.tfm", TfmFile("AffineTransform_double_3_3",
                                                                 "1 0 0 0 1 0 0 0 1 10 20 30", "0 0 0"));
  vtkNew<vtkMatrix4x4> m;
  std::string error;
  ASSERT_TRUE(rp::ReadTransformFile(path, m, error)) << error;
  ExpectMatrix(m, {1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, -30}, 1e-12);
}

TEST(TransformIO, RotationsOfEveryLinearKind) {
  // fromParentLPS = [Rz(90°) | (1,2,3)], Rz = [[0,-1,0],[1,0,0],[0,0,1]].
  // S·M·S keeps Rz and gives translation (-1,-2,3); its inverse is [Rzᵀ | -Rzᵀ(-1,-2,3)] =
  // [[0,1,0, 2],[-1,0,0,-1],[0,0,1,-3]].
  const std::vector<double> expected = {0, 1, 0, 2, -1, 0, 0, -1, 0, 0, 1, -3};
  const double halfPi = std::acos(0.0);
  std::ostringstream euler, versor, similarity, affineFloat;
  euler.precision(17);
  euler << "0 0 " << halfPi << " 1 2 3";
  const double s45 = std::sqrt(0.5);
  versor.precision(17);
  versor << "0 0 " << s45 << " 1 2 3";
  const struct {
    std::string name, text;
  } files[] = {
      {"affine.tfm", TfmFile("AffineTransform_double_3_3", "0 -1 0 1 0 0 0 0 1 1 2 3", "0 0 0")},
      {"affine_float.txt", TfmFile("AffineTransform_float_3_3", "0 -1 0 1 0 0 0 0 1 1 2 3", "0 0 0")},
      {"matrixoffset.tfm", TfmFile("MatrixOffsetTransformBase_double_3_3", "0 -1 0 1 0 0 0 0 1 1 2 3", "0 0 0")},
      {"euler.tfm", TfmFile("Euler3DTransform_double_3_3", euler.str(), "0 0 0")},
      {"versor.tfm", TfmFile("VersorRigid3DTransform_double_3_3", versor.str(), "0 0 0")},
  };
  for (const auto& f : files) {
    vtkNew<vtkMatrix4x4> m;
    std::string error;
    ASSERT_TRUE(rp::ReadTransformFile(WriteText(f.name, f.text), m, error)) << f.name << ": " << error;
    SCOPED_TRACE(f.name);
    ExpectMatrix(m, expected, f.name == "affine_float.txt" ? 1e-6 : 1e-12);
  }
}

TEST(TransformIO, CentreOfRotationAndScale) {
  // Euler Rz(90°) about centre c = (5,0,0) with translation t = (1,2,3): offset = c + t - Rz·c
  // = (6,-3,3). In RAS (-6,3,3); toParentRAS translation = -Rzᵀ(-6,3,3) = (-3,-6,-3).
  const double halfPi = std::acos(0.0);
  std::ostringstream euler;
  euler.precision(17);
  euler << "0 0 " << halfPi << " 1 2 3";
  vtkNew<vtkMatrix4x4> m;
  std::string error;
  ASSERT_TRUE(rp::ReadTransformFile(
      WriteText("euler_centre.tfm", TfmFile("Euler3DTransform_double_3_3", euler.str(), "5 0 0")), m, error))
      << error;
  ExpectMatrix(m, {0, 1, 0, -3, -1, 0, 0, -6, 0, 0, 1, -3}, 1e-12);

  // Similarity: identity versor, translation (2,4,6), scale 2: fromParentLPS = [2I | (2,4,6)],
  // RAS [2I | (-2,-4,6)], inverse [I/2 | (1,2,-3)].
  ASSERT_TRUE(rp::ReadTransformFile(
      WriteText("similarity.tfm", TfmFile("Similarity3DTransform_double_3_3", "0 0 0 2 4 6 2", "0 0 0")), m, error))
      << error;
  ExpectMatrix(m, {0.5, 0, 0, 1, 0, 0.5, 0, 2, 0, 0, 0.5, -3}, 1e-12);
}

TEST(TransformIO, CompositeOfLinearTransforms) {
  // ITK applies a composite's last transform first: T(x) = Affine(Translation(x)).
  // Translation (1,2,3) then Rz(90°): fromParentLPS = [Rz | Rz·(1,2,3)] = [Rz | (-2,1,3)].
  // RAS: [Rz | (2,-1,3)]; inverse [Rzᵀ | -Rzᵀ(2,-1,3)] = [Rzᵀ | (1,2,-3)].
  const std::string text =
      "#Insight Transform File V1.0\n#Transform 0\nTransform: CompositeTransform_double_3_3\n"
      "#Transform 1\nTransform: AffineTransform_double_3_3\nParameters: 0 -1 0 1 0 0 0 0 1 0 0 0\n"
      "FixedParameters: 0 0 0\n"
      "#Transform 2\nTransform: TranslationTransform_double_3_3\nParameters: 1 2 3\nFixedParameters: \n";
  vtkNew<vtkMatrix4x4> m;
  std::string error;
  ASSERT_TRUE(rp::ReadTransformFile(WriteText("composite.tfm", text), m, error)) << error;
  ExpectMatrix(m, {0, 1, 0, 1, -1, 0, 0, 2, 0, 0, 1, -3}, 1e-12);
}

vtkSmartPointer<vtkMatrix4x4> RandomRigid(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-180, 180), shift(-200, 200), axis(-1, 1);
  vtkNew<vtkTransform> t;
  t->Translate(shift(rng), shift(rng), shift(rng));
  t->RotateWXYZ(angle(rng), axis(rng), axis(rng), axis(rng) + 0.01);
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  m->DeepCopy(t->GetMatrix());
  return m;
}

TEST(TransformIO, WritesAffineFromParentLPSAndRoundTrips) {
  std::mt19937 rng(7);
  for (const char* ext : {".tfm", ".txt", ".h5"}) {
    for (int trial = 0; trial < 5; ++trial) {
      auto toParent = RandomRigid(rng);
      const std::string path = OutputDir() + "/roundtrip" + std::to_string(trial) + ext;
      std::string error;
      ASSERT_TRUE(rp::WriteTransformFile(path, toParent, error)) << ext << ": " << error;
      vtkNew<vtkMatrix4x4> back;
      ASSERT_TRUE(rp::ReadTransformFile(path, back, error)) << ext << ": " << error;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {  // two 4x4 inversions (and HDF5): relative 1e-12
          const double expected = toParent->GetElement(i, j);
          EXPECT_NEAR(back->GetElement(i, j), expected, 1e-12 * (1 + std::abs(expected))) << ext;
        }
    }
  }

  // The written text: AffineTransform_double_3_3 holding S·inverse(toParentRAS)·S.
  vtkNew<vtkMatrix4x4> toParent;
  const double e[16] = {1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, -30, 0, 0, 0, 1};
  toParent->DeepCopy(e);
  const std::string path = OutputDir() + "/written.tfm";
  std::string error;
  ASSERT_TRUE(rp::WriteTransformFile(path, toParent, error)) << error;
  const std::string text = ReadText(path);
  EXPECT_NE(text.find("#Insight Transform File V1.0"), std::string::npos) << text;
  EXPECT_NE(text.find("Transform: AffineTransform_double_3_3"), std::string::npos) << text;
  EXPECT_NE(text.find("Parameters: 1 0 0 0 1 0 0 0 1 10 20 30"), std::string::npos) << text;
  EXPECT_NE(text.find("FixedParameters: 0 0 0"), std::string::npos) << text;
}

TEST(TransformIO, RefusesBadFilesAndMatrices) {
  vtkNew<vtkMatrix4x4> m;
  const double e[16] = {2, 0, 0, 1, 0, 2, 0, 2, 0, 0, 2, 3, 0, 0, 0, 1};
  m->DeepCopy(e);
  std::string error;
  EXPECT_FALSE(rp::ReadTransformFile(OutputDir() + "/missing.tfm", m, error));
  EXPECT_NE(error.find("missing.tfm"), std::string::npos);
  EXPECT_FALSE(rp::ReadTransformFile(WriteText("garbage.tfm", "hello\n"), m, error));
  EXPECT_NE(error.find("garbage.tfm"), std::string::npos);
  EXPECT_FALSE(rp::ReadTransformFile(
      WriteText("short.tfm", TfmFile("AffineTransform_double_3_3", "1 0 0 0 1", "0 0 0")), m, error));
  EXPECT_FALSE(rp::ReadTransformFile(
      WriteText("singular.tfm", TfmFile("AffineTransform_double_3_3", "0 0 0 0 0 0 0 0 0 1 2 3", "0 0 0")), m,
      error));
  EXPECT_NE(error.find("singular"), std::string::npos) << error;
  EXPECT_FALSE(rp::ReadTransformFile(WriteText("empty.h5", ""), m, error));
  for (int i = 0; i < 16; ++i) EXPECT_EQ(m->GetElement(i / 4, i % 4), e[i]);  // untouched

  vtkNew<vtkMatrix4x4> singular;
  singular->SetElement(0, 0, 0);
  EXPECT_FALSE(rp::WriteTransformFile(OutputDir() + "/singular_out.tfm", singular, error));
  EXPECT_FALSE(std::filesystem::exists(OutputDir() + "/singular_out.tfm"));
  EXPECT_FALSE(rp::WriteTransformFile(OutputDir() + "/unknown.xyz", m, error));
}

TEST(TransformIO, RegisteredAsNodeStorage) {
  vtkNew<vtkRPLinearTransformNode> node;
  const rp::NodeStorage* storage = rp::FindNodeStorage(node);
  ASSERT_NE(storage, nullptr);
  EXPECT_EQ(storage->DefaultExtension(), ".tfm");
  EXPECT_EQ(storage->NodeClassForFiles(), "vtkRPLinearTransformNode");
  for (const char* name : {"x.tfm", "x.TXT", "x.h5"}) EXPECT_EQ(rp::FindNodeStorageForFile(name), storage) << name;

  vtkNew<vtkRPScene> scene;
  std::string error;
  vtkRPNode* loaded = rp::LoadDataFile(
      scene, WriteText("TrackerToRAS.tfm", TfmFile("AffineTransform_double_3_3", "1 0 0 0 1 0 0 0 1 10 20 30", "0 0 0")),
      error);
  ASSERT_NE(loaded, nullptr) << error;
  auto* t = vtkRPLinearTransformNode::SafeDownCast(loaded);
  ASSERT_NE(t, nullptr);
  ExpectMatrix(t->GetMatrixTransformToParent(), {1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, -30}, 1e-12);
  const std::string h5 = OutputDir() + "/TrackerToRAS.h5";
  ASSERT_TRUE(rp::SaveDataFile(t, h5, error)) << error;
  vtkNew<vtkMatrix4x4> back;
  ASSERT_TRUE(rp::ReadTransformFile(h5, back, error)) << error;
  ExpectMatrix(back, {1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, -30}, 1e-12);
}

}  // namespace
