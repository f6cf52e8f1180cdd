#include "rpModuleManager.h"

#include <dlfcn.h>
#include <link.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpAtomicFile.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {

namespace {

constexpr int ManifestFormat = 1;

// What identifies a build of a library: its size and modification time.
bool LibraryStamp(const std::string& path, long long& size, long long& mtimeNs) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return false;
  size = static_cast<long long>(s.st_size);
  mtimeNs = static_cast<long long>(s.st_mtim.tv_sec) * 1000000000LL + s.st_mtim.tv_nsec;
  return true;
}

std::vector<std::string> ModuleFiles(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  for (const auto& item : fs::directory_iterator(folder, ec)) {
    const std::string name = item.path().filename().string();
    if (name.rfind("libRoboPlanModule", 0) == 0 && item.path().extension() == ".so") files.push_back(item.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The libraries a loaded module brought into this process (those not loaded before, `before`),
// dependencies before their dependents: loading them one by one in this order relocates each
// against a short scope (the program's libraries, then itself and its own dependencies) instead
// of the whole new tree, which is most of a module's load time (ld.so's symbol lookups).
std::vector<std::string> LibrariesInLoadOrder(void* handle, const std::set<std::string>& before) {
  link_map* module = nullptr;
  if (::dlinfo(handle, RTLD_DI_LINKMAP, &module) != 0 || !module) return {};
  std::map<std::string, link_map*> bySoname;  // by file name, as DT_NEEDED names them
  link_map* first = module;
  while (first->l_prev) first = first->l_prev;
  for (link_map* m = first; m; m = m->l_next)
    if (m->l_name && *m->l_name) bySoname.emplace(fs::path(m->l_name).filename().string(), m);
  std::vector<std::string> order;
  std::set<link_map*> visited;
  std::function<void(link_map*)> visit = [&](link_map* m) {
    if (!visited.insert(m).second) return;
    const char* strtab = nullptr;
    for (const ElfW(Dyn)* d = m->l_ld; d->d_tag != DT_NULL; ++d)
      if (d->d_tag == DT_STRTAB)  // relocated in memory by ld.so on x86-64, else file-relative
        strtab = reinterpret_cast<const char*>(d->d_un.d_ptr < m->l_addr ? m->l_addr + d->d_un.d_ptr : d->d_un.d_ptr);
    if (strtab)
      for (const ElfW(Dyn)* d = m->l_ld; d->d_tag != DT_NULL; ++d)
        if (d->d_tag == DT_NEEDED) {
          auto it = bySoname.find(strtab + d->d_un.d_val);
          if (it != bySoname.end()) visit(it->second);
        }
    const std::string path = m->l_name ? m->l_name : "";
    if (m != module && !path.empty() && !before.count(path)) order.push_back(fs::path(path).lexically_normal().string());
  };
  visit(module);
  return order;
}

// A manifest names the libraries of the module's own tree (the folder above the module folder:
// build/lib or <prefix>/lib) relative to the module's folder, and the system's absolutely, so a
// build tree copied or moved elsewhere loads its own libraries, never the original's.
std::string ManifestLibraryEntry(const fs::path& library, const fs::path& moduleFolder) {
  const fs::path tree = moduleFolder.parent_path();
  const fs::path inTree = library.lexically_relative(tree);
  if (inTree.empty() || *inTree.begin() == "..") return library.string();
  return library.lexically_relative(moduleFolder).string();
}

std::string ManifestLibraryPath(const std::string& entry, const fs::path& moduleFolder) {
  const fs::path path(entry);
  return path.is_absolute() ? entry : (moduleFolder / path).lexically_normal().string();
}

std::set<std::string> LoadedLibraries() {
  std::set<std::string> names;
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        if (info->dlpi_name && *info->dlpi_name) static_cast<std::set<std::string>*>(data)->insert(info->dlpi_name);
        return 0;
      },
      &names);
  return names;
}

}  // namespace

struct ModuleManager::Entry {
  std::string Path;
  ModuleManifest Manifest;
  std::vector<std::string> Libraries;  // what it loads, dependencies first (from its manifest)
  std::unique_ptr<Module> Instance;  // null while the module is known from its manifest only
  void* Handle = nullptr;            // dlopen handle; the code stays mapped until exit
  bool SetUp = false;
  bool Failed = false;               // its library failed to load (reported once)
  std::vector<Command> Commands;
};

ModuleManager::ModuleManager() = default;

ModuleManager::~ModuleManager() {
  // Destroy modules in reverse setup order.
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

std::string ModuleManager::ManifestPath(const std::string& libraryPath) { return libraryPath + ".json"; }

bool ModuleManager::ReadFreshManifest(const std::string& libraryPath, ModuleManifest& manifest,
                                      std::vector<std::string>& libraries) const {
  std::string text, error;
  long long size = 0, mtime = 0;
  if (!LibraryStamp(libraryPath, size, mtime) || !ReadFile(ManifestPath(libraryPath), text, error)) return false;
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (!doc.is_object() || doc.value("roboplanModuleManifest", 0) != ManifestFormat ||
      doc.value("abi", 0) != ROBOPLAN_MODULE_ABI_VERSION || !doc.contains("library") ||
      doc["library"].value("size", -1LL) != size || doc["library"].value("mtimeNs", -1LL) != mtime)
    return false;  // no manifest, or the library was rebuilt or replaced since: load it to see
  try {
    manifest.Name = doc.at("name").get<std::string>();
    manifest.Title = doc.value("title", manifest.Name);
    manifest.Dependencies = doc.value("dependencies", std::vector<std::string>{});
    libraries.clear();
    const fs::path folder = fs::path(libraryPath).parent_path();
    for (const std::string& entry : doc.value("libraries", std::vector<std::string>{}))
      libraries.push_back(ManifestLibraryPath(entry, folder));
    manifest.Commands.clear();
    for (const auto& command : doc.value("commands", nlohmann::json::array()))
      manifest.Commands.push_back({command.at("name").get<std::string>(), command.value("summary", std::string())});
  } catch (const nlohmann::json::exception&) {
    return false;
  }
  return !manifest.Name.empty();
}

bool ModuleManager::WriteManifest(const std::string& libraryPath, std::string& error) {
  ModuleManager manager;
  const std::set<std::string> before = LoadedLibraries();
  // RTLD_NOW here (LoadModuleFile is lazy): a symbol the module cannot resolve fails the build.
  void* check = ::dlopen(libraryPath.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!check) {
    const char* why = ::dlerror();
    error = std::string("cannot load ") + libraryPath + ": " + (why ? why : "unknown error");
    return false;
  }
  if (!manager.LoadModuleFile(libraryPath) || manager.Entries.size() != 1) {
    error = manager.Failures.empty() ? "no module in " + libraryPath : manager.Failures[0].Reason;
    return false;
  }
  Entry& entry = *manager.Entries[0];
  vtkNew<vtkRPScene> scene;
  try {
    entry.Instance->Setup(scene);
    entry.Commands = entry.Instance->Commands();
  } catch (const std::exception& e) {
    error = "setting up " + libraryPath + " threw: " + e.what();
    return false;
  }
  long long size = 0, mtime = 0;
  if (!LibraryStamp(libraryPath, size, mtime)) {
    error = "cannot read " + libraryPath;
    return false;
  }
  nlohmann::json commands = nlohmann::json::array();
  for (const Command& command : entry.Commands) commands.push_back({{"name", command.Name}, {"summary", command.Summary}});
  std::vector<std::string> libraries;
  const fs::path folder = fs::absolute(libraryPath).parent_path().lexically_normal();
  for (const std::string& library : LibrariesInLoadOrder(check, before))
    libraries.push_back(ManifestLibraryEntry(library, folder));
  const nlohmann::json doc = {{"roboplanModuleManifest", ManifestFormat},
                              {"abi", ROBOPLAN_MODULE_ABI_VERSION},
                              {"library", {{"file", fs::path(libraryPath).filename().string()}, {"size", size}, {"mtimeNs", mtime}}},
                              {"name", entry.Instance->Name()},
                              {"title", entry.Instance->Title()},
                              {"dependencies", entry.Instance->Dependencies()},
                              {"commands", commands},
                              {"libraries", libraries}};
  return WriteFileAtomically(ManifestPath(libraryPath), doc.dump(2) + "\n", error);
}

ModuleManager::Entry* ModuleManager::FindEntry(const std::string& name) const {
  for (const auto& entry : this->Entries)
    if (entry->Manifest.Name == name) return entry.get();
  return nullptr;
}

bool ModuleManager::LoadModuleFile(const std::string& path) {
  // Lazy binding: the module's functions (and those of the libraries it brings) are bound when
  // first called, not all at load; the build checked they all resolve (WriteManifest).
  void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
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
  Entry* entry = this->FindEntry(module->Name());
  if (entry && (entry->Instance || entry->Path != path)) {
    // Earlier folders in the search path win (e.g. a build tree over ROBOPLAN_MODULE_PATH).
    return true;
  }
  if (!entry) {
    this->Entries.push_back(std::make_unique<Entry>());
    entry = this->Entries.back().get();
    entry->Path = path;
  }
  entry->Manifest.Name = module->Name();
  entry->Manifest.Title = module->Title();
  entry->Manifest.Dependencies = module->Dependencies();
  entry->Instance = std::move(module);
  entry->Handle = handle;
  return true;
}

void ModuleManager::AddModule(std::unique_ptr<Module> module, const std::string& origin) {
  if (!module || this->FindEntry(module->Name())) return;
  auto entry = std::make_unique<Entry>();
  entry->Manifest.Name = module->Name();
  entry->Manifest.Title = module->Title();
  entry->Manifest.Dependencies = module->Dependencies();
  entry->Instance = std::move(module);
  entry->Path = origin;
  this->Entries.push_back(std::move(entry));
}

int ModuleManager::DiscoverModules(const std::vector<std::string>& searchPaths) {
  for (const auto& folder : searchPaths) {
    for (const auto& file : ModuleFiles(folder)) {
      ModuleManifest manifest;
      std::vector<std::string> libraries;
      if (!this->ReadFreshManifest(file, manifest, libraries)) {
        this->LoadModuleFile(file);  // no manifest to trust: ask the module itself
        continue;
      }
      if (this->FindEntry(manifest.Name)) continue;  // earlier folders win
      auto entry = std::make_unique<Entry>();
      entry->Path = file;
      entry->Manifest = std::move(manifest);
      entry->Libraries = std::move(libraries);
      this->Entries.push_back(std::move(entry));
    }
  }
  return static_cast<int>(this->Entries.size());
}

bool ModuleManager::Load(Entry& entry) {
  if (entry.Instance) return true;
  if (entry.Failed) return false;
  const std::string name = entry.Manifest.Name, path = entry.Path;
  entry.Failed = true;
  // Its libraries one by one, dependencies first (see LibrariesInLoadOrder); one that does not
  // load (the system changed since the build) is left to the module's own load, which names it.
  for (const std::string& library : entry.Libraries) ::dlopen(library.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (!this->LoadModuleFile(path)) return false;
  if (!entry.Instance) {
    this->Failures.push_back({path, "the library is not module " + name + " as its manifest says (rebuild it)"});
    return false;
  }
  entry.Failed = false;
  return true;
}

std::string ModuleManager::PanelPath(const std::string& modulePath, const std::string& name) {
  return (fs::path(modulePath).parent_path() / ("libRoboPlanPanel" + name + ".so")).string();
}

QWidget* ModuleManager::CreatePanel(const std::string& name, vtkRPScene* scene, QWidget* parent) {
  Entry* entry = this->FindEntry(name);
  if (!entry || !entry->SetUp || !entry->Handle) return nullptr;  // not set up, or built in
  const std::string path = PanelPath(entry->Path, name);
  std::error_code ec;
  if (!fs::exists(path, ec)) return nullptr;  // a module without a panel
  void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    this->Failures.push_back({path, std::string("cannot load the panel: ") + (why ? why : "unknown error")});
    return nullptr;
  }
  using CreatePanelFunction = QWidget* (*)(vtkObject*, vtkRPScene*, QWidget*);
  auto create = reinterpret_cast<CreatePanelFunction>(::dlsym(handle, "roboplan_create_module_panel"));
  if (!create) {
    this->Failures.push_back({path, "not a RoboPlan panel plugin: missing roboplan_create_module_panel"});
    return nullptr;
  }
  try {
    QWidget* panel = create(entry->Instance->Logic(), scene, parent);
    if (!panel) this->Failures.push_back({path, "the panel plugin made no panel for module " + name});
    return panel;
  } catch (const std::exception& e) {
    this->Failures.push_back({path, std::string("roboplan_create_module_panel threw: ") + e.what()});
    return nullptr;
  }
}

int ModuleManager::LoadModules(const std::vector<std::string>& searchPaths, vtkRPScene* scene) {
  this->DiscoverModules(searchPaths);
  return this->LoadAll(scene);
}

int ModuleManager::LoadAll(vtkRPScene* scene) {
  for (size_t i = 0; i < this->Entries.size(); ++i) this->Load(*this->Entries[i]);
  return this->SetupModules(scene);
}

const Command* ModuleManager::LoadCommand(const std::string& name, vtkRPScene* scene) {
  if (const Command* command = this->FindCommand(name)) return command;
  Entry* owner = nullptr;
  for (const auto& entry : this->Entries)
    for (const auto& command : entry->Manifest.Commands)
      if (!owner && command.Name == name) owner = entry.get();
  if (!owner) {
    // Modules loaded without a manifest list their commands once set up.
    this->SetupModules(scene);
    return this->FindCommand(name);
  }
  // The owner and, through SetupModules, its dependencies (loaded there on demand).
  if (!this->Load(*owner)) return nullptr;
  this->SetupModules(scene);
  return this->FindCommand(name);
}

int ModuleManager::SetupModules(vtkRPScene* scene) {
  // Depth-first topological order of the loaded modules (a dependency known from its manifest
  // only is loaded here); modules with a missing or cyclic dependency are refused.
  std::map<std::string, Entry*> byName;
  for (auto& entry : this->Entries) byName[entry->Manifest.Name] = entry.get();
  std::vector<Entry*> order;
  std::set<std::string> done, visiting, failed;
  std::function<bool(Entry*)> visit = [&](Entry* entry) -> bool {
    const std::string name = entry->Manifest.Name;
    if (done.count(name)) return true;
    if (failed.count(name)) return false;
    if (!this->Load(*entry)) {
      failed.insert(name);
      return false;
    }
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
  for (size_t i = 0; i < this->Entries.size(); ++i)
    if (this->Entries[i]->Instance) visit(this->Entries[i].get());

  int setUp = 0;
  for (Entry* entry : order) {
    if (!entry->SetUp) {
      try {
        entry->Instance->Setup(scene);
        entry->Commands = entry->Instance->Commands();
        entry->SetUp = true;
      } catch (const std::exception& e) {
        this->Failures.push_back({entry->Path, "Setup of module " + entry->Manifest.Name + " threw: " + e.what()});
        continue;
      }
    }
    ++setUp;
  }
  // Modules set up first, in setup order; then those still known from their manifest only.
  // Loaded modules that could not be set up are destroyed (their code stays mapped).
  std::vector<std::unique_ptr<Entry>> kept;
  for (Entry* entry : order) {
    if (!entry->SetUp) continue;
    for (auto& owned : this->Entries)
      if (owned.get() == entry) kept.push_back(std::move(owned));
  }
  for (auto& owned : this->Entries) {
    if (owned && !owned->Instance && !owned->Failed) kept.push_back(std::move(owned));
    else if (owned) owned->Instance.reset();
  }
  this->Entries = std::move(kept);
  return setUp;
}

std::vector<Module*> ModuleManager::GetModules() const {
  std::vector<Module*> modules;
  for (const auto& entry : this->Entries)
    if (entry->SetUp) modules.push_back(entry->Instance.get());
  return modules;
}

Module* ModuleManager::GetModule(const std::string& name) const {
  const Entry* entry = this->FindEntry(name);
  return entry && entry->SetUp ? entry->Instance.get() : nullptr;
}

std::string ModuleManager::GetModulePath(const std::string& name) const {
  const Entry* entry = this->FindEntry(name);
  return entry ? entry->Path : std::string();
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
    for (const auto& command : entry->Commands) all.emplace_back(entry->Manifest.Name, command);
  }
  return all;
}

std::vector<std::pair<std::string, ModuleManifest::CommandInfo>> ModuleManager::ListCommands() const {
  std::vector<std::pair<std::string, ModuleManifest::CommandInfo>> all;
  for (const auto& entry : this->Entries) {
    if (entry->SetUp) {
      for (const auto& command : entry->Commands) all.push_back({entry->Manifest.Name, {command.Name, command.Summary}});
    } else {
      for (const auto& command : entry->Manifest.Commands) all.push_back({entry->Manifest.Name, command});
    }
  }
  return all;
}

int ModuleManager::UnloadedModuleCount() const {
  return static_cast<int>(std::count_if(this->Entries.begin(), this->Entries.end(),
                                        [](const std::unique_ptr<Entry>& e) { return !e->Instance; }));
}

void* ModuleManager::FindSymbol(const std::string& module, const char* symbol) const {
  const Entry* entry = this->FindEntry(module);
  return entry && entry->SetUp && entry->Handle ? ::dlsym(entry->Handle, symbol) : nullptr;
}

}  // namespace rp
