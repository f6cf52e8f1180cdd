#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <vtkNew.h>

#include "rpModuleManager.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

TEST(ModuleManager, LoadsPluginsInDependencyOrderAndReportsBrokenOnes) {
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  const int count = manager.LoadModules({ROBOPLAN_TEST_MODULE_DIR}, scene);
  EXPECT_EQ(count, 2);
  ASSERT_NE(manager.GetModule("TestGood"), nullptr);
  ASSERT_NE(manager.GetModule("TestDependent"), nullptr);
  EXPECT_NE(scene->GetFirstNodeByName("TestDependent after TestGood"), nullptr);
  auto modules = manager.GetModules();
  ASSERT_EQ(modules.size(), 2u);
  EXPECT_EQ(modules[0]->Name(), "TestGood");
  EXPECT_EQ(modules[1]->Name(), "TestDependent");
  // The broken plugin is reported with its path and the reason; the others still load.
  ASSERT_EQ(manager.GetFailures().size(), 1u);
  EXPECT_NE(manager.GetFailures()[0].Path.find("libRoboPlanModuleTestBroken.so"), std::string::npos);
  EXPECT_NE(manager.GetFailures()[0].Reason.find("roboplan_create_module"), std::string::npos);
  const rp::Command* command = manager.FindCommand("test-good");
  ASSERT_NE(command, nullptr);
  rp::CommandContext context;
  context.Arguments = {"a", "b"};
  EXPECT_EQ(command->Run(context), 44);
}

TEST(ModuleManager, NotASharedObjectAndMissingDependencyAreReported) {
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "bad-modules";
  fs::create_directories(dir);
  std::ofstream(dir / "libRoboPlanModuleGarbage.so") << "this is not an ELF file";
  fs::copy_file(fs::path(ROBOPLAN_TEST_MODULE_DIR) / "libRoboPlanModuleTestDependent.so",
                dir / "libRoboPlanModuleTestDependent.so", fs::copy_options::overwrite_existing);
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  EXPECT_EQ(manager.LoadModules({dir.string()}, scene), 0);
  ASSERT_EQ(manager.GetFailures().size(), 2u);
  bool sawGarbage = false, sawDependency = false;
  for (const auto& failure : manager.GetFailures()) {
    sawGarbage |= failure.Path.find("Garbage") != std::string::npos &&
                  failure.Reason.find("cannot load shared object") != std::string::npos;
    sawDependency |= failure.Reason.find("needs module TestGood") != std::string::npos;
  }
  EXPECT_TRUE(sawGarbage);
  EXPECT_TRUE(sawDependency);
}
