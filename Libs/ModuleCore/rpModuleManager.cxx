#include "rpModuleManager.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace rp {

struct ModuleManager::Entry {
  std::unique_ptr<Module> Instance;
  std::string Path;
  void* Handle = nullptr;  // dlopen handle; closed after the module is destroyed
  bool SetUp = false;
  std::vector<Command> Commands;
};

ModuleManager::ModuleManager() = default;

ModuleManager::~ModuleManager() {
  // Destroy modules in reverse setup order, then unload their code.
  for (auto it = this->Entries.rbegin(); it != this->Entries.rend(); ++it) {
    (*it)->Commands.clear();
    (*it)->Instance.reset();
  }
  // Shared objects stay mapped until exit: VTK object factories and static storage
  // registrations made by modules may still be referenced by the scene.
}

std::vector<std::string> ModuleManager::DefaultSearchPaths() {
  std::vector<std::string> paths;
  char exe[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  if (n > 0) {
    exe[n] = '\0';
    const fs::path dir = fs::path(exe).parent_path();
    paths.push_back((dir.parent_path() / "lib" / "roboplan-modules").string());
  }
  if (const char* env = std::getenv("ROBOPLAN_MODULE_PATH")) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':')) {
      if (!item.empty()) paths.push_back(item);
    }
  }
  return paths;
}

bool ModuleManager::LoadModuleFile(const std::string& path) {
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    this->Failures.push_back({path, std::string("cannot load shared object: ") + (why ? why : "unknown error")});
    return false;
  }
  using AbiFunction = int (*)();
  using CreateFunction = Module* (*)();
  auto abi = reinterpret_cast<AbiFunction>(::dlsym(handle, "roboplan_module_abi_version"));
  auto create = reinterpret_cast<CreateFunction>(::dlsym(handle, "roboplan_create_module"));
  if (!abi || !create) {
    this->Failures.push_back({path, "not a RoboPlan module: missing roboplan_create_module/roboplan_module_abi_version"});
    ::dlclose(handle);
    return false;
  }
  if (abi() != ROBOPLAN_MODULE_ABI_VERSION) {
    this->Failures.push_back({path, "built for module ABI " + std::to_string(abi()) + ", this program needs " +
                                        std::to_string(ROBOPLAN_MODULE_ABI_VERSION) + " (rebuild the module)"});
    ::dlclose(handle);
    return false;
  }
  std::unique_ptr<Module> module;
  try {
    module.reset(create());
  } catch (const std::exception& e) {
    this->Failures.push_back({path, std::string("roboplan_create_module threw: ") + e.what()});
    return false;
  }
  if (!module) {
    this->Failures.push_back({path, "roboplan_create_module returned no module"});
    return false;
  }
  if (this->GetModule(module->Name())) {
    // Earlier folders in the search path win (e.g. a build tree over ROBOPLAN_MODULE_PATH).
    return true;
  }
  auto entry = std::make_unique<Entry>();
  entry->Instance = std::move(module);
  entry->Path = path;
  entry->Handle = handle;
  this->Entries.push_back(std::move(entry));
  return true;
}

void ModuleManager::AddModule(std::unique_ptr<Module> module, const std::string& origin) {
  if (!module || this->GetModule(module->Name())) return;
  auto entry = std::make_unique<Entry>();
  entry->Instance = std::move(module);
  entry->Path = origin;
  this->Entries.push_back(std::move(entry));
}

int ModuleManager::LoadModules(const std::vector<std::string>& searchPaths, vtkRPScene* scene) {
  for (const auto& folder : searchPaths) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) continue;
    std::vector<std::string> files;
    for (const auto& item : fs::directory_iterator(folder, ec)) {
      const std::string name = item.path().filename().string();
      if (name.rfind("libRoboPlanModule", 0) == 0 && item.path().extension() == ".so") files.push_back(item.path().string());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) this->LoadModuleFile(file);
  }
  return this->SetupModules(scene);
}

int ModuleManager::SetupModules(vtkRPScene* scene) {
  // Depth-first topological order; modules with a missing or cyclic dependency are refused.
  std::map<std::string, Entry*> byName;
  for (auto& entry : this->Entries) byName[entry->Instance->Name()] = entry.get();
  std::vector<Entry*> order;
  std::set<std::string> done, visiting, failed;
  std::function<bool(Entry*)> visit = [&](Entry* entry) -> bool {
    const std::string name = entry->Instance->Name();
    if (done.count(name)) return true;
    if (failed.count(name)) return false;
    if (visiting.count(name)) {
      this->Failures.push_back({entry->Path, "module " + name + " is part of a dependency cycle"});
      failed.insert(name);
      return false;
    }
    visiting.insert(name);
    for (const auto& dependency : entry->Instance->Dependencies()) {
      auto it = byName.find(dependency);
      if (it == byName.end()) {
        this->Failures.push_back({entry->Path, "module " + name + " needs module " + dependency + ", which is not loaded"});
        failed.insert(name);
        visiting.erase(name);
        return false;
      }
      if (!visit(it->second)) {
        if (!failed.count(name)) {
          this->Failures.push_back({entry->Path, "module " + name + " needs module " + dependency + ", which failed"});
          failed.insert(name);
        }
        visiting.erase(name);
        return false;
      }
    }
    visiting.erase(name);
    done.insert(name);
    order.push_back(entry);
    return true;
  };
  for (auto& entry : this->Entries) visit(entry.get());

  int setUp = 0;
  std::vector<std::unique_ptr<Entry>> kept;
  for (Entry* entry : order) {
    if (!entry->SetUp) {
      try {
        entry->Instance->Setup(scene);
        entry->Commands = entry->Instance->Commands();
        entry->SetUp = true;
      } catch (const std::exception& e) {
        this->Failures.push_back({entry->Path, "Setup of module " + entry->Instance->Name() + " threw: " + e.what()});
        continue;
      }
    }
    ++setUp;
  }
  // Keep only modules that are set up, in setup order.
  for (Entry* entry : order) {
    if (!entry->SetUp) continue;
    for (auto& owned : this->Entries) {
      if (owned.get() == entry) kept.push_back(std::move(owned));
    }
  }
  for (auto& owned : this->Entries) {
    if (owned) owned->Instance.reset();  // failed modules are destroyed; their code stays mapped
  }
  this->Entries = std::move(kept);
  return setUp;
}

std::vector<Module*> ModuleManager::GetModules() const {
  std::vector<Module*> modules;
  for (const auto& entry : this->Entries) modules.push_back(entry->Instance.get());
  return modules;
}

Module* ModuleManager::GetModule(const std::string& name) const {
  for (const auto& entry : this->Entries) {
    if (entry->Instance && entry->Instance->Name() == name) return entry->Instance.get();
  }
  return nullptr;
}

std::string ModuleManager::GetModulePath(const std::string& name) const {
  for (const auto& entry : this->Entries) {
    if (entry->Instance && entry->Instance->Name() == name) return entry->Path;
  }
  return {};
}

const Command* ModuleManager::FindCommand(const std::string& name) const {
  for (const auto& entry : this->Entries) {
    for (const auto& command : entry->Commands) {
      if (command.Name == name) return &command;
    }
  }
  return nullptr;
}

std::vector<std::pair<std::string, Command>> ModuleManager::GetAllCommands() const {
  std::vector<std::pair<std::string, Command>> all;
  for (const auto& entry : this->Entries) {
    for (const auto& command : entry->Commands) all.emplace_back(entry->Instance->Name(), command);
  }
  return all;
}

}  // namespace rp
