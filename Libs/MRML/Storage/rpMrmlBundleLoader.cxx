// What RoboPlanMRMLStorage holds of .mrb bundles (rpMrmlBundle.h): the forwarders to the zip side
// in libRoboPlanMrmlBundle.so beside this library (rpMrmlBundleEntries.h), loaded on the first
// bundle read or written, and what needs no zip (the main scene's choice, temporary folders).
#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "rpMrmlBundleEntries.h"
#include "rpSiblingLibrary.h"

namespace fs = std::filesystem;

namespace rp {
namespace {
// The entry `symbol`; nullptr with `error` naming the bundle and the library that did not load.
template <typename Function>
Function BundleEntry(const char* symbol, const std::string& zipPath, std::string& error) {
  std::string why;
  const auto function =
      SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&FindMainScene), bundle::Library, symbol, why);
  if (!function) error = "'" + zipPath + "': Slicer bundles (.mrb) are not available: " + why;
  return function;
}
}  // namespace

bool UnpackBundle(const std::string& zipPath, const std::string& folder, uint64_t maxBytes,
                  std::vector<std::string>& entries, std::string& error) {
  const auto unpack = BundleEntry<bundle::UnpackFunction>(bundle::UnpackEntry, zipPath, error);
  return unpack && unpack(zipPath, folder, maxBytes, entries, error);
}

bool PackBundle(const std::string& folder, const std::string& rootName, const std::string& zipPath,
                std::string& error) {
  const auto pack = BundleEntry<bundle::PackFunction>(bundle::PackEntry, zipPath, error);
  return pack && pack(folder, rootName, zipPath, error);
}

std::string FindMainScene(const std::vector<std::string>& entries) {
  std::string best;
  long bestDepth = 0;
  for (const std::string& name : entries) {
    if (name.size() < 5 || name.substr(name.size() - 5) != ".mrml") continue;
    const long depth = std::count(name.begin(), name.end(), '/');
    if (best.empty() || depth < bestDepth || (depth == bestDepth && name < best)) {
      best = name;
      bestDepth = depth;
    }
  }
  return best;
}

TemporaryFolder::TemporaryFolder(const std::string& prefix, const std::string& parent) {
  std::error_code ec;
  std::string pattern = ((parent.empty() ? fs::temp_directory_path(ec) : fs::path(parent)) / (prefix + "-XXXXXX")).string();
  if (mkdtemp(pattern.data())) this->Folder = pattern;
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ec;
  if (!this->Folder.empty()) fs::remove_all(this->Folder, ec);
}

}  // namespace rp
