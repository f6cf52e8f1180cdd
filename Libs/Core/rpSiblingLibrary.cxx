#include "rpSiblingLibrary.h"

#include <dlfcn.h>

#include <filesystem>
#include <map>
#include <mutex>

namespace rp {

void* SiblingLibrarySymbol(const void* anchor, const std::string& library, const char* symbol, std::string& error,
                           bool onlyIfLoaded) {
  static std::mutex lock;
  static std::map<std::string, void*> handles;  // by path; kept until exit
  Dl_info info{};
  if (!::dladdr(anchor, &info) || !info.dli_fname) {
    error = "cannot find the folder of the library that needs " + library;
    return nullptr;
  }
  const std::string path = (std::filesystem::path(info.dli_fname).parent_path() / library).string();
  std::lock_guard<std::mutex> guard(lock);
  void*& handle = handles[path];
  if (!handle) handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL | (onlyIfLoaded ? RTLD_NOLOAD : 0));
  if (!handle && onlyIfLoaded) {
    handles.erase(path);
    return nullptr;
  }
  if (!handle) {
    const char* why = ::dlerror();
    error = "cannot load " + path + ": " + (why ? why : "unknown error");
    handles.erase(path);
    return nullptr;
  }
  void* address = ::dlsym(handle, symbol);
  if (!address) error = path + " has no function " + symbol + " (rebuild it)";
  return address;
}

}  // namespace rp
