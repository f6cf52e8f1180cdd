// TemplateKey logic: files loaded through the one loader are counted by class, and a file that
// cannot be read is named while what loaded before stays.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include <vtkNew.h>
#include <vtkSphereSource.h>

#include "rpModelIO.h"
#include "rpTemplateKeyCommand.h"
#include "rpTestOutput.h"
#include "vtkRPScene.h"
#include "vtkRPTemplateKeyLogic.h"

namespace {

std::string WriteSphere(const std::string& name) {
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  const std::string path = (rptest::TestDir(name) / name).string();  // TestDir empties its folder
  std::string error;
  EXPECT_TRUE(rp::WriteModelFile(path, sphere->GetOutput(), error)) << error;
  return path;
}

TEST(TemplateKeyLogic, CountsTheLoadedNodesByClass) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTemplateKeyLogic> logic;
  logic->SetScene(scene);
  std::string error;
  ASSERT_TRUE(logic->LoadFiles({WriteSphere("a.vtp"), WriteSphere("b.stl")}, error)) << error;
  const auto counts = logic->CountNodesByClass();
  ASSERT_EQ(counts.count("vtkRPModelNode"), 1u);
  EXPECT_EQ(counts.at("vtkRPModelNode"), 2);
}

TEST(TemplateKeyLogic, AnUnreadableFileIsNamedAndWhatLoadedStays) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTemplateKeyLogic> logic;
  logic->SetScene(scene);
  std::string error;
  EXPECT_FALSE(logic->LoadFiles({WriteSphere("c.vtp"), "/nowhere/missing.vtp"}, error));
  EXPECT_NE(error.find("missing.vtp"), std::string::npos) << error;
  EXPECT_EQ(logic->CountNodesByClass().at("vtkRPModelNode"), 1);
}

TEST(TemplateKeyCommand, PrintsTheCountsAsJson) {
  std::ostringstream out, err;
  EXPECT_EQ(rp::RunTemplateKeySummaryCommand({WriteSphere("d.vtp"), "--json"}, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("\"vtkRPModelNode\": 1"), std::string::npos) << out.str();
  EXPECT_EQ(rp::RunTemplateKeySummaryCommand({"--no-such-option"}, out, err), 2);
}

}  // namespace
