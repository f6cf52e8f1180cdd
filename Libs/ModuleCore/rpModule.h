#pragma once
// The interface every run-time loadable module implements (the qSlicerAbstractModule of
// RoboPlan). A module's shared object exports
//     extern "C" rp::Module* roboplan_create_module();
//     extern "C" int roboplan_module_abi_version();   // must return ROBOPLAN_MODULE_ABI_VERSION
// (use ROBOPLAN_DECLARE_MODULE(ClassName) at the end of the plugin's .cxx).
// Its Qt panel, if it has one, is a plugin of its own beside it, libRoboPlanPanel<Name>.so, which
// exports
//     extern "C" QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene* scene, QWidget* parent);
// (ROBOPLAN_MODULE_PANEL_EXPORT): the viewer loads it when it shows the panel
// (rp::ModuleManager::CreatePanel); commands never load Qt.
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

class vtkRPScene;
class vtkObject;
class QWidget;

#define ROBOPLAN_MODULE_ABI_VERSION 3  // 2: CommandContext carries the output streams; 3: panels in their own plugin

namespace rp {

/// What a CLI subcommand gets: its arguments (after the subcommand name), a scene, and where to
/// print (a host or a test may capture them; commands never write to std::cout/std::cerr).
struct CommandContext {
  std::vector<std::string> Arguments;
  vtkRPScene* Scene = nullptr;    // a scene the command may use (headless; owned by the host)
  std::ostream* Out = &std::cout;  // results: text, or the --json document
  std::ostream* Err = &std::cerr;  // messages, warnings and errors
};

/// A `roboplan <name> ...` subcommand contributed by a module. Returns the process exit code:
/// 0 success, 1 the work failed (message on stderr), 2 bad arguments.
struct Command {
  std::string Name;
  std::string Summary;
  std::function<int(CommandContext&)> Run;
};

class Module {
 public:
  virtual ~Module() = default;

  /// Unique name, e.g. "LandmarkRegistration". Dependencies refer to it.
  virtual std::string Name() const = 0;
  /// Human title for menus and panels, e.g. "Landmark Registration".
  virtual std::string Title() const { return this->Name(); }
  /// Names of modules that must be loaded and set up first.
  virtual std::vector<std::string> Dependencies() const { return {}; }

  /// Called once, after the module's dependencies are set up: register node classes, storage,
  /// create the logic and attach it to the scene.
  virtual void Setup(vtkRPScene* scene) { (void)scene; }
  /// The module's logic object (no Qt), or nullptr.
  virtual vtkObject* Logic() { return nullptr; }
  /// CLI subcommands this module contributes.
  virtual std::vector<Command> Commands() { return {}; }
};

}  // namespace rp

#define ROBOPLAN_DECLARE_MODULE(ClassName)                                               \
  extern "C" __attribute__((visibility("default"))) rp::Module* roboplan_create_module() { \
    return new ClassName();                                                              \
  }                                                                                      \
  extern "C" __attribute__((visibility("default"))) int roboplan_module_abi_version() {    \
    return ROBOPLAN_MODULE_ABI_VERSION;                                                  \
  }

// Exports a panel plugin's factory: ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(...).
#define ROBOPLAN_MODULE_PANEL_EXPORT extern "C" __attribute__((visibility("default")))
