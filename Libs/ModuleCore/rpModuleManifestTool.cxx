// roboplan-module-manifest <libRoboPlanModuleX.so>...: writes each module's manifest
// (<library>.json: name, title, dependencies, commands; rpModuleManager.h) from the module itself.
// The build runs it after linking a module, and the install on the installed copy, so that
// `roboplan <command>` loads only the module that owns the command.
#include <iostream>
#include <string>

#include "rpModuleManager.h"

int main(int argc, char* argv[]) {
  if (argc < 2) {
    std::cerr << "usage: roboplan-module-manifest <module library>...\n";
    return 2;
  }
  for (int i = 1; i < argc; ++i) {
    std::string error;
    if (!rp::ModuleManager::WriteManifest(argv[i], error)) {
      std::cerr << "roboplan-module-manifest: " << error << "\n";
      return 1;
    }
  }
  return 0;
}
