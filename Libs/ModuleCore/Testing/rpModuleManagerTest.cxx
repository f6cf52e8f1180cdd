#include <gtest/gtest.h>

#include <link.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include <nlohmann/json.hpp>
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

namespace {
// The good and the dependent test modules copied into a fresh folder, with their manifests.
fs::path ModulesWithManifests(const std::string& name) {
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* file : {"libRoboPlanModuleTestGood.so", "libRoboPlanModuleTestDependent.so"}) {
    fs::copy_file(fs::path(ROBOPLAN_TEST_MODULE_DIR) / file, dir / file);
    std::string error;
    EXPECT_TRUE(rp::ModuleManager::WriteManifest((dir / file).string(), error)) << error;
    EXPECT_TRUE(fs::exists(rp::ModuleManager::ManifestPath((dir / file).string())));
  }
  return dir;
}
}  // namespace

TEST(ModuleManager, ManifestsKeepModulesUnloadedUntilTheirCommandRuns) {
  const fs::path dir = ModulesWithManifests("manifests");
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  EXPECT_EQ(manager.DiscoverModules({dir.string()}), 2);
  EXPECT_EQ(manager.UnloadedModuleCount(), 2);
  EXPECT_TRUE(manager.GetModules().empty());
  // The commands and their summaries come from the manifests.
  std::map<std::string, std::string> commands;
  for (const auto& [module, command] : manager.ListCommands()) commands[command.Name] = module + ": " + command.Summary;
  EXPECT_EQ(commands["test-good"], "TestGood: returns 42");
  EXPECT_EQ(commands["test-dependent"], "TestDependent: returns 45");
  EXPECT_EQ(manager.LoadCommand("no-such-command", scene), nullptr);
  EXPECT_EQ(manager.UnloadedModuleCount(), 2);
  // A command loads its module only.
  const rp::Command* good = manager.LoadCommand("test-good", scene);
  ASSERT_NE(good, nullptr);
  rp::CommandContext context;
  context.Arguments = {"a"};
  EXPECT_EQ(good->Run(context), 43);
  ASSERT_EQ(manager.GetModules().size(), 1u);
  EXPECT_EQ(manager.GetModules()[0]->Name(), "TestGood");
  EXPECT_EQ(manager.UnloadedModuleCount(), 1);
  // A module's dependencies are set up before it.
  const rp::Command* dependent = manager.LoadCommand("test-dependent", scene);
  ASSERT_NE(dependent, nullptr);
  EXPECT_EQ(dependent->Run(context), 45);
  EXPECT_NE(scene->GetFirstNodeByName("TestDependent after TestGood"), nullptr);
  EXPECT_EQ(manager.UnloadedModuleCount(), 0);
  EXPECT_TRUE(manager.GetFailures().empty());
}

TEST(ModuleManager, DependenciesOfACommandsModuleLoadFirst) {
  const fs::path dir = ModulesWithManifests("manifests-dependent");
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  manager.DiscoverModules({dir.string()});
  ASSERT_NE(manager.LoadCommand("test-dependent", scene), nullptr);
  const auto modules = manager.GetModules();
  ASSERT_EQ(modules.size(), 2u);
  EXPECT_EQ(modules[0]->Name(), "TestGood");
  EXPECT_EQ(modules[1]->Name(), "TestDependent");
  EXPECT_NE(scene->GetFirstNodeByName("TestDependent after TestGood"), nullptr);
}

TEST(ModuleManager, AStaleManifestIsNotTrusted) {
  const fs::path dir = ModulesWithManifests("manifests-stale");
  // The library changes after its manifest was written (a rebuild without the build's step, a
  // copy over it): the manager asks the module itself.
  std::ofstream(dir / "libRoboPlanModuleTestGood.so", std::ios::app) << "trailing bytes";
  // A manifest that lies about the module it describes is not trusted either.
  const fs::path dependent = dir / "libRoboPlanModuleTestDependent.so";
  std::string text, error;
  {
    std::ifstream in(rp::ModuleManager::ManifestPath(dependent.string()));
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t at = text.find("\"TestDependent\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 15, "\"SomeOtherName\"");
  std::ofstream(rp::ModuleManager::ManifestPath(dependent.string())) << text;
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  manager.DiscoverModules({dir.string()});
  EXPECT_EQ(manager.UnloadedModuleCount(), 1);  // TestGood was loaded to see what it is
  // The lying manifest's module is loaded for its command and refused by name.
  EXPECT_EQ(manager.LoadCommand("test-dependent", scene), nullptr);
  bool named = false;
  for (const auto& failure : manager.GetFailures())
    named |= failure.Reason.find("not module SomeOtherName") != std::string::npos;
  EXPECT_TRUE(named);
  // The good module still runs.
  const rp::Command* good = manager.LoadCommand("test-good", scene);
  ASSERT_NE(good, nullptr);
  rp::CommandContext context;
  EXPECT_EQ(good->Run(context), 42);
}

// A panel comes from the plugin beside its module, loaded when asked for; a module without one
// has no panel and no failure; a plugin without the factory is named.
TEST(ModuleManager, PanelsComeFromTheirPluginWhenAskedFor) {
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  ASSERT_EQ(manager.LoadModules({ROBOPLAN_TEST_MODULE_DIR}, scene), 2);
  const size_t failuresBefore = manager.GetFailures().size();  // the broken module's
  auto* parent = reinterpret_cast<QWidget*>(&manager);  // never dereferenced: the test plugin returns it
  EXPECT_EQ(manager.CreatePanel("TestGood", scene, parent), parent);
  EXPECT_EQ(manager.CreatePanel("NoSuchModule", scene, parent), nullptr);
  EXPECT_EQ(manager.GetFailures().size(), failuresBefore);
  EXPECT_EQ(manager.CreatePanel("TestDependent", scene, parent), nullptr);
  ASSERT_EQ(manager.GetFailures().size(), failuresBefore + 1);
  EXPECT_NE(manager.GetFailures().back().Path.find("libRoboPlanPanelTestDependent.so"), std::string::npos);
  EXPECT_NE(manager.GetFailures().back().Reason.find("roboplan_create_module_panel"), std::string::npos);

  const fs::path dir = ModulesWithManifests("no-panels");  // the modules alone
  rp::ModuleManager alone;
  ASSERT_EQ(alone.LoadModules({dir.string()}, scene), 2);
  EXPECT_EQ(alone.CreatePanel("TestGood", scene, parent), nullptr);
  EXPECT_TRUE(alone.GetFailures().empty());
}

// What a command loads is what it needs: a module's panel is a plugin of its own that only the
// viewer loads, so no module maps Qt for its commands but the viewer's and the demo's (the demo
// draws the viewer's screenshots). ITK is loaded where it runs (the image and transform IO, CT-MR
// registration, segmentation edits and the bone split: libraries of their own), so no module
// maps it at start-up. Each module's manifest lists the libraries loading it maps.
TEST(ModuleManager, TheProjectsCommandsLoadNoQtAndNoItk) {
  int modules = 0;
  for (const auto& item : fs::directory_iterator(ROBOPLAN_MODULE_DIR)) {
    const std::string file = item.path().filename().string();
    if (file.rfind("libRoboPlanModule", 0) != 0 || item.path().extension() != ".so") continue;
    std::ifstream in(rp::ModuleManager::ManifestPath(item.path().string()));
    ASSERT_TRUE(in) << "no manifest beside " << file;
    const nlohmann::json manifest = nlohmann::json::parse(in);
    const std::string name = manifest.at("name").get<std::string>();
    for (const auto& library : manifest.at("libraries")) {
      const std::string mapped = fs::path(library.get<std::string>()).filename().string();
      EXPECT_NE(mapped.rfind("libITK", 0), 0u) << name << " loads " << library;
      EXPECT_NE(mapped.rfind("libitk", 0), 0u) << name << " loads " << library;
      if (name != "Viewer" && name != "Demo") EXPECT_NE(mapped.rfind("libQt5", 0), 0u) << name << " loads " << library;
    }
    if (name == "Viewer" || name == "Demo") continue;
    ++modules;
  }
  EXPECT_GE(modules, 7);
}

namespace {
// Where each RoboPlan library mapped into this process was loaded from.
std::map<std::string, std::string> MappedRoboPlanLibraries() {
  std::map<std::string, std::string> mapped;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        const fs::path path(info->dlpi_name ? info->dlpi_name : "");
        if (path.filename().string().rfind("libRoboPlan", 0) == 0)
          static_cast<std::map<std::string, std::string>*>(data)->emplace(path.filename().string(), path.string());
        return 0;
      },
      &mapped);
  return mapped;
}

void CopyKeepingTime(const fs::path& from, const fs::path& to) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  fs::last_write_time(to, fs::last_write_time(from));  // the manifest checks the module's time
}
}  // namespace

// A build tree copied elsewhere (the module folder and the libraries beside it, with their
// manifests) loads its own libraries: a manifest names the tree's libraries relative to the
// module folder, so a command run from the copy maps nothing of the original tree.
TEST(ModuleManager, ACopiedBuildTreeLoadsItsOwnLibraries) {
  const fs::path modules = fs::path(ROBOPLAN_MODULE_DIR), lib = modules.parent_path();
  const fs::path copy = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "copied-tree" / "lib";
  fs::remove_all(copy.parent_path());
  fs::create_directories(copy / modules.filename());
  for (const auto& item : fs::directory_iterator(lib))
    if (item.is_regular_file() && item.path().extension() == ".so") CopyKeepingTime(item.path(), copy / item.path().filename());
  for (const auto& item : fs::directory_iterator(modules))
    if (item.is_regular_file()) CopyKeepingTime(item.path(), copy / modules.filename() / item.path().filename());

  const std::map<std::string, std::string> before = MappedRoboPlanLibraries();
  ASSERT_EQ(before.count("libRoboPlanDrillingLogic.so"), 0u) << "the test program must not link the module's logic";
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  const int discovered = manager.DiscoverModules({(copy / modules.filename()).string()});
  ASSERT_GE(discovered, 7);
  EXPECT_EQ(manager.UnloadedModuleCount(), discovered) << "every copied manifest is trusted";
  ASSERT_NE(manager.LoadCommand("drill", scene), nullptr);
  EXPECT_TRUE(manager.GetFailures().empty()) << manager.GetFailures()[0].Path << ": " << manager.GetFailures()[0].Reason;
  int loaded = 0;
  for (const auto& [name, path] : MappedRoboPlanLibraries()) {
    if (before.count(name)) continue;
    ++loaded;
    EXPECT_EQ(fs::path(path).lexically_normal().string().rfind(copy.lexically_normal().string(), 0), 0u)
        << name << " was loaded from " << path;
  }
  EXPECT_GE(loaded, 3) << "the Drilling module and its logic came from the copy";
}
