#include "rpResources.h"

#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace rp {

std::string ResourcesDirectory() {
  if (const char* env = std::getenv("ROBOPLAN_RESOURCES_DIR"); env && *env) return env;
  char exe[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  if (n > 0) {
    exe[n] = '\0';
    const fs::path installed = fs::path(exe).parent_path().parent_path() / "share" / "roboplan" / "Resources";
    std::error_code ec;
    if (fs::is_directory(installed, ec)) return installed.string();
  }
  return ROBOPLAN_SOURCE_RESOURCES_DIR;
}

std::string ResourcePath(const std::string& relative) { return ResourcesDirectory() + "/" + relative; }

}  // namespace rp
