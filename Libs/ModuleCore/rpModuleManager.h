#pragma once
// Finds, loads and sets up run-time loadable modules (shared objects exporting
// roboplan_create_module, see rpModule.h). Search path: the build or install tree's
// lib/roboplan-modules beside the executable, then every folder in ROBOPLAN_MODULE_PATH
// (colon-separated). Dependencies are set up first; a module that fails to load (bad file,
// missing symbol, wrong ABI, missing dependency, dependency cycle) is reported with its path and
// the reason, and the others still load.
#include <memory>
#include <string>
#include <vector>

#include "rpModule.h"

namespace rp {

struct ModuleLoadFailure {
  std::string Path;    // shared object (or module name when the file loaded but setup failed)
  std::string Reason;
};

class ModuleManager {
 public:
  ModuleManager();
  ~ModuleManager();
  ModuleManager(const ModuleManager&) = delete;
  ModuleManager& operator=(const ModuleManager&) = delete;

  /// Default folders: <exe dir>/../lib/roboplan-modules, then $ROBOPLAN_MODULE_PATH entries.
  static std::vector<std::string> DefaultSearchPaths();

  /// Loads every libRoboPlanModule*.so in the folders (first found wins for a given module
  /// name), orders them by dependencies and calls Setup(scene) on each. Returns the number of
  /// modules set up.
  int LoadModules(const std::vector<std::string>& searchPaths, vtkRPScene* scene);
  /// Loads one shared object (used by tests). Returns false and records a failure.
  bool LoadModuleFile(const std::string& path);
  /// Adds an already constructed module (e.g. built into the executable or a test).
  void AddModule(std::unique_ptr<Module> module, const std::string& origin = "(built in)");
  /// Orders loaded modules by dependencies and sets them up against the scene.
  int SetupModules(vtkRPScene* scene);

  /// Modules in setup order.
  std::vector<Module*> GetModules() const;
  Module* GetModule(const std::string& name) const;
  std::string GetModulePath(const std::string& name) const;
  const std::vector<ModuleLoadFailure>& GetFailures() const { return this->Failures; }

  /// The CLI command with this name from any module, or nullptr.
  const Command* FindCommand(const std::string& name) const;
  std::vector<std::pair<std::string, Command>> GetAllCommands() const;  // (module name, command)

 private:
  struct Entry;
  std::vector<std::unique_ptr<Entry>> Entries;  // in setup order once SetupModules ran
  std::vector<ModuleLoadFailure> Failures;
};

}  // namespace rp
