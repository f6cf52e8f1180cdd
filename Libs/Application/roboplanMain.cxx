// `roboplan`: one executable. With a subcommand it runs headless (subcommands come from the
// modules, plus `modules`); without one, or with scene/data files or folders (an argument
// that is an existing path is data, not a command), it opens the viewer. A command loads only
// the module that owns it (found from the modules' manifests, rpModuleManager.h); the viewer
// and `modules` load them all.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpModuleManager.h"
#include "vtkRPScene.h"

namespace {

void PrintUsage(const rp::ModuleManager& manager) {
  std::cout << "usage: roboplan [<scene or data files>...]     open the viewer\n"
               "       roboplan <command> [arguments] [--json] [--help]\n\ncommands:\n";
  std::printf("  %-18s %s\n", "modules", "list the loaded modules, their commands and load failures");
  for (const auto& [module, command] : manager.ListCommands()) {
    std::printf("  %-18s %s  [%s]\n", command.Name.c_str(), command.Summary.c_str(), module.c_str());
  }
  std::cout << "\nmodules are loaded from <prefix>/lib/roboplan-modules and $ROBOPLAN_MODULE_PATH\n";
}

void ReportFailures(const rp::ModuleManager& manager) {
  for (const auto& failure : manager.GetFailures()) {
    std::cerr << "roboplan: module not loaded: " << failure.Path << ": " << failure.Reason << "\n";
  }
}

int ListModules(rp::ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& args) {
  rp::ArgParser parser("modules", "List the loaded modules, their commands and any module that failed to load.");
  if (const auto exitCode = parser.ParseCommand(args, std::cout, std::cerr)) return *exitCode;
  manager.LoadAll(scene);  // what loads and what fails, not what the manifests say (after --help and bad arguments)
  if (parser.Json()) {
    nlohmann::json doc;
    doc["modules"] = nlohmann::json::array();
    for (rp::Module* module : manager.GetModules()) {
      nlohmann::json commands = nlohmann::json::array();
      for (const auto& [owner, command] : manager.GetAllCommands()) {
        if (owner == module->Name()) commands.push_back(command.Name);
      }
      doc["modules"].push_back({{"name", module->Name()}, {"title", module->Title()},
                                {"dependencies", module->Dependencies()}, {"path", manager.GetModulePath(module->Name())},
                                {"commands", commands}});
    }
    doc["failures"] = nlohmann::json::array();
    for (const auto& failure : manager.GetFailures()) {
      doc["failures"].push_back({{"path", failure.Path}, {"reason", failure.Reason}});
    }
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  for (rp::Module* module : manager.GetModules()) {
    std::cout << module->Name() << " — " << module->Title() << "\n    " << manager.GetModulePath(module->Name()) << "\n";
    for (const auto& dependency : module->Dependencies()) std::cout << "    depends on " << dependency << "\n";
  }
  for (const auto& failure : manager.GetFailures()) {
    std::cout << "FAILED " << failure.Path << "\n    " << failure.Reason << "\n";
  }
  return 0;
}


bool NamesCommand(const std::string& name, const rp::ModuleManager& manager) {
  if (name == "modules") return true;
  for (const auto& command : manager.ListCommands())
    if (command.second.Name == name) return true;
  return false;
}

// The first argument is data to open in the viewer, not a command, when it names no command and
// is an existing file or folder (`roboplan /data/knee/CT`, a DICOM folder), or looks like a file
// name (has a '.': a missing scene is then reported by the viewer, not as an unknown command).
// A command name wins over a file of that name in the working folder (`./mesh` opens the file).
bool IsDataArgument(const std::string& argument, const rp::ModuleManager& manager) {
  if (argument.empty() || argument[0] == '-' || NamesCommand(argument, manager)) return false;
  std::error_code ec;
  return std::filesystem::exists(argument, ec) || argument.find('.') != std::string::npos;
}

}  // namespace

int main(int argc, char* argv[]) {
  std::vector<std::string> args(argv + 1, argv + argc);
  // Run as `roboplan-<command>` (a link in lib/roboplan-cli: one executable per command, the way
  // 3D Slicer finds CLI modules), it is `roboplan <command>`.
  const std::string program = std::filesystem::path(argv[0]).filename().string();
  const bool linkedCommand = program.rfind("roboplan-", 0) == 0;
  if (linkedCommand) args.insert(args.begin(), program.substr(std::string("roboplan-").size()));
  vtkNew<vtkRPScene> scene;
  rp::ModuleManager manager;
  manager.DiscoverModules(rp::ModuleManager::DefaultSearchPaths());

  const bool wantsViewer = !linkedCommand && (args.empty() || IsDataArgument(args[0], manager));
  if (wantsViewer) {
    manager.LoadAll(scene);  // every module's panel, and the viewer (Libs/Application/ViewerModule.cxx)
    using RunViewerFunction = int (*)(int, char**, rp::ModuleManager*, vtkRPScene*, const std::vector<std::string>*);
    if (auto run = reinterpret_cast<RunViewerFunction>(manager.FindSymbol("Viewer", "roboplan_run_viewer"))) {
      ReportFailures(manager);
      return run(argc, argv, &manager, scene, &args);
    }
    if (args.empty()) {
      ReportFailures(manager);
      PrintUsage(manager);
      std::cerr << "\nroboplan: this build has no viewer (configured with ROBOPLAN_BUILD_GUI=OFF, or its module did "
                   "not load)\n";
      return 2;
    }
  }
  const std::string name = args.empty() ? "" : args[0];
  const std::vector<std::string> rest(args.begin() + (args.empty() ? 0 : 1), args.end());
  if (name == "--help" || name == "-h" || name == "help") {
    PrintUsage(manager);
    return 0;
  }
  if (name == "modules") return ListModules(manager, scene, rest);
  const rp::Command* command = manager.LoadCommand(name, scene);
  if (!command) {
    ReportFailures(manager);
    for (const auto& [module, offered] : manager.ListCommands())
      if (offered.Name == name) {
        std::cerr << "roboplan: command '" << name << "' is in module " << module << ", which did not load\n";
        return 1;
      }
    std::cerr << "roboplan: unknown command '" << name << "'\n\n";
    PrintUsage(manager);
    return 2;
  }
  ReportFailures(manager);
  rp::CommandContext context;
  context.Arguments = rest;
  context.Scene = scene;
  try {
    return command->Run(context);
  } catch (const std::exception& e) {
    std::cerr << "roboplan " << name << ": " << e.what() << "\n";
    return 1;
  }
}
