// The one loader (rpDataLoader.h): a path finds its reader, the nodes land in the scene, a failed
// read leaves the scene as it was, a scene file is read by its own reader, and a format added by
// one class and one registration is found like the built-in ones.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

#include "rpDataLoader.h"
#include "rpModelIO.h"
#include "rpSceneIO.h"
#include "rpTestOutput.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace {

std::string WriteBall(const fs::path& dir, const std::string& name) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(10.0);
  sphere->Update();
  const std::string path = (dir / name).string();
  std::string error;
  EXPECT_TRUE(rp::WriteModelFile(path, sphere->GetOutput(), error)) << error;
  return path;
}

// A format of the test's own: one class, one registration line (what README "Extending RoboPlan" asks).
class EchoReader : public rp::DataReader {
 public:
  std::string Description() const override { return "Test echo"; }
  bool CanRead(const std::string& path) const override { return rp::HasExtension(path, ".rpecho"); }
  bool Read(const std::string& path, const rp::ReadOptions& options, vtkRPScene* scene,
            rp::LoadResult& result) const override {
    auto node = scene->CreateNodeByClass("vtkRPModelNode");
    node->SetName(fs::path(path).stem().string());
    result.Details["series"] = options.Series;
    result.Nodes.push_back(node);
    return true;
  }
};
const bool echoRegistered = rp::RegisterDataReader(std::make_shared<EchoReader>());

TEST(DataLoader, ANodeFileLandsInTheSceneNamedAfterTheFile) {
  const fs::path dir = rptest::TestDir("node-file");
  const std::string path = WriteBall(dir, "ball.vtp");
  vtkNew<vtkRPScene> scene;
  const rp::LoadResult result = rp::LoadPath(scene, path);
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_EQ(result.Reader, "Node file");
  ASSERT_EQ(result.Nodes.size(), 1u);
  auto* model = vtkRPModelNode::SafeDownCast(result.Nodes.front());
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->GetName(), "ball");
  EXPECT_EQ(model->GetScene(), scene.GetPointer());
  EXPECT_EQ(scene->GetNumberOfNodes(), 1);
  EXPECT_EQ(result.Details["nodeClass"], "vtkRPModelNode");
  EXPECT_EQ(model->GetPolyData()->GetNumberOfPoints(), 50);  // vtkSphereSource's 8x8 default
}

TEST(DataLoader, AFailedReadLeavesTheSceneAsItWas) {
  const fs::path dir = rptest::TestDir("failed-read");
  vtkNew<vtkRPScene> scene;
  ASSERT_TRUE(rp::LoadPath(scene, WriteBall(dir, "kept.vtp")).Ok);
  std::ofstream((dir / "broken.vtp").string()) << "<VTKFile this is not";
  const rp::LoadResult broken = rp::LoadPath(scene, (dir / "broken.vtp").string());
  EXPECT_FALSE(broken.Ok);
  EXPECT_NE(broken.Error.find("broken.vtp"), std::string::npos) << broken.Error;
  EXPECT_TRUE(broken.Nodes.empty());
  std::ofstream((dir / "notes.unknown").string()) << "notes";
  const rp::LoadResult unknown = rp::LoadPath(scene, (dir / "notes.unknown").string());
  EXPECT_FALSE(unknown.Ok);
  EXPECT_NE(unknown.Error.find("no reader for this file type"), std::string::npos) << unknown.Error;
  const rp::LoadResult missing = rp::LoadPath(scene, (dir / "missing.unknown").string());
  EXPECT_NE(missing.Error.find("no such file or folder"), std::string::npos) << missing.Error;
  EXPECT_EQ(scene->GetNumberOfNodes(), 1);
}

TEST(DataLoader, ASceneFileIsReadIntoTheSceneByItsOwnReader) {
  const fs::path dir = rptest::TestDir("scene-file");
  vtkNew<vtkRPScene> saved;
  ASSERT_TRUE(rp::LoadPath(saved, WriteBall(dir, "ball.vtp")).Ok);
  std::string error;
  ASSERT_TRUE(rp::SaveScene(saved, (dir / "knee.rpscene").string(), error)) << error;
  ASSERT_NE(rp::FindDataReader((dir / "knee.rpscene").string()), nullptr);
  EXPECT_TRUE(rp::FindDataReader((dir / "knee.rpscene").string())->ReadsIntoScene());

  vtkNew<vtkRPScene> loaded;
  const rp::LoadResult result = rp::LoadPath(loaded, (dir / "knee.rpscene").string());
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_EQ(result.Reader, "RoboPlan scene");
  EXPECT_EQ(loaded->GetNumberOfNodes(), saved->GetNumberOfNodes());
  EXPECT_EQ(result.Details["nodesLoaded"], saved->GetNumberOfNodes());
}

TEST(DataLoader, LoadSingleNodeRefusesASceneFileWithoutReadingIt) {
  const fs::path dir = rptest::TestDir("single-node");
  vtkNew<vtkRPScene> saved;
  ASSERT_TRUE(rp::LoadPath(saved, WriteBall(dir, "ball.vtp")).Ok);
  std::string error;
  ASSERT_TRUE(rp::SaveScene(saved, (dir / "knee.rpscene").string(), error)) << error;
  vtkNew<vtkRPScene> scene;
  rp::LoadResult result;
  EXPECT_EQ(rp::LoadSingleNode(scene, (dir / "knee.rpscene").string(), result), nullptr);
  EXPECT_NE(result.Error.find("RoboPlan scene"), std::string::npos) << result.Error;
  EXPECT_EQ(scene->GetNumberOfNodes(), 0);
  vtkRPNode* ball = rp::LoadSingleNode(scene, (dir / "ball.vtp").string(), result);
  ASSERT_NE(ball, nullptr) << result.Error;
  EXPECT_EQ(ball->GetScene(), scene.GetPointer());
}

TEST(DataLoader, AFormatRegisteredByOneClassIsFoundAndGetsTheReadOptions) {
  ASSERT_TRUE(echoRegistered);
  vtkNew<vtkRPScene> scene;
  rp::ReadOptions options;
  options.Series = "1.2.3#2";
  const rp::LoadResult result = rp::LoadPath(scene, "/nowhere/echo.rpecho", options);
  ASSERT_TRUE(result.Ok) << result.Error;
  EXPECT_EQ(result.Reader, "Test echo");
  EXPECT_EQ(result.Details["series"], "1.2.3#2");
  ASSERT_EQ(scene->GetNumberOfNodes(), 1);
  EXPECT_EQ(result.Nodes.front()->GetName(), "echo");
}

}  // namespace
