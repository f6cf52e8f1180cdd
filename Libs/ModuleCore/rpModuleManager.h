#pragma once
// Finds, loads and sets up run-time loadable modules (shared objects exporting
// roboplan_create_module, see rpModule.h). Search path: the build or install tree's
// lib/roboplan-modules beside the executable, then every folder in ROBOPLAN_MODULE_PATH
// (colon-separated). Dependencies are set up first; a module that fails to load (bad file,
// missing symbol, wrong ABI, missing dependency, dependency cycle) is reported with its path and
// the reason, and the others still load.
//
// Loading a module maps every library it links (VTK, ITK, Qt, DCMTK, ...), which costs more
// than most commands' work. So a module's manifest — `<library>.json` beside it, written at build
// time by `roboplan-module-manifest` from the module itself (name, title, dependencies, commands
// with their summaries, and the libraries loading it maps: those of its own tree relative to
// the module folder, so a copied tree loads its own) — says what it offers without loading it:
// DiscoverModules reads the manifests, LoadCommand loads only the module that owns a command
// (and its dependencies).
// A module without a manifest, or whose library changed since its manifest was written (size,
// modification time, ABI), is loaded at discovery, as before.
#include <memory>
#include <string>
#include <vector>

#include "rpModule.h"

namespace rp {

struct ModuleLoadFailure {
  std::string Path;    // shared object (or module name when the file loaded but setup failed)
  std::string Reason;
};

/// What a module offers, as its manifest says (or as the loaded module says).
struct ModuleManifest {
  std::string Name, Title;
  std::vector<std::string> Dependencies;
  struct CommandInfo {
    std::string Name, Summary;
  };
  std::vector<CommandInfo> Commands;
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
  /// Finds the modules in the folders without loading those with a fresh manifest (the others
  /// are loaded, not set up). Returns the number of modules found.
  int DiscoverModules(const std::vector<std::string>& searchPaths);
  /// The command `name`: loads and sets up the module that offers it (and its dependencies)
  /// when it is not yet. nullptr when no module offers it or its module failed (GetFailures).
  const Command* LoadCommand(const std::string& name, vtkRPScene* scene);
  /// Loads and sets up every module found (the viewer, `roboplan modules`).
  int LoadAll(vtkRPScene* scene);
  /// Loads one shared object (used by tests). Returns false and records a failure.
  bool LoadModuleFile(const std::string& path);
  /// Adds an already constructed module (e.g. built into the executable or a test).
  void AddModule(std::unique_ptr<Module> module, const std::string& origin = "(built in)");
  /// Orders loaded modules by dependencies and sets them up against the scene.
  int SetupModules(vtkRPScene* scene);

  /// Modules set up, in setup order.
  std::vector<Module*> GetModules() const;
  Module* GetModule(const std::string& name) const;
  std::string GetModulePath(const std::string& name) const;
  const std::vector<ModuleLoadFailure>& GetFailures() const { return this->Failures; }

  /// The CLI command with this name from a module set up, or nullptr (see LoadCommand).
  const Command* FindCommand(const std::string& name) const;
  std::vector<std::pair<std::string, Command>> GetAllCommands() const;  // (module name, command), set up only
  /// Every command of every module found, set up or not: (module name, command name and summary).
  std::vector<std::pair<std::string, ModuleManifest::CommandInfo>> ListCommands() const;
  /// Modules found whose manifest let them stay unloaded so far.
  int UnloadedModuleCount() const;
  /// The Qt panel of module `name` (set up) from its panel plugin beside it
  /// (libRoboPlanPanel<Name>.so, loaded on first call), on `scene`, as a child of `parent`.
  /// nullptr when the module has none; when the plugin fails to load, also a failure naming it.
  QWidget* CreatePanel(const std::string& name, vtkRPScene* scene, QWidget* parent);
  /// `libRoboPlanPanel<Name>.so` beside the module library at `modulePath`.
  static std::string PanelPath(const std::string& modulePath, const std::string& name);
  /// An entry point a module set up exports (dlsym in its library), or nullptr.
  void* FindSymbol(const std::string& module, const char* symbol) const;

  /// `<library>.json`: where a module library's manifest lives.
  static std::string ManifestPath(const std::string& libraryPath);
  /// Loads the module library, sets it up against a scratch scene and writes its manifest
  /// (the build does this after linking a module). False names the problem.
  static bool WriteManifest(const std::string& libraryPath, std::string& error);

 private:
  struct Entry;
  bool ReadFreshManifest(const std::string& libraryPath, ModuleManifest& manifest,
                         std::vector<std::string>& libraries) const;
  Entry* FindEntry(const std::string& name) const;
  bool Load(Entry& entry);  // loads a manifest-only entry's library
  std::vector<std::unique_ptr<Entry>> Entries;  // set up (in setup order) first, then the others
  std::vector<ModuleLoadFailure> Failures;
};

}  // namespace rp
