#include "rpSceneDataFiles.h"

#include "rpAtomicFile.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

std::string Join(const std::string& subfolder, const std::string& name) {
  return subfolder.empty() ? name : subfolder + "/" + name;
}

}  // namespace

bool SceneDataFiles::IsOwnable(const std::string& name) {
  if (name.empty() || name.front() == '/') return false;
  for (const fs::path& part : fs::path(name))
    if (part.empty() || part == "." || part == "..") return false;
  return true;
}

SceneDataFiles::SceneDataFiles(fs::path folder, const std::set<std::string>& owned) : Folder(std::move(folder)) {
  for (const std::string& name : owned)
    if (IsOwnable(name)) this->Owned.insert(name);
}

SceneDataFiles::~SceneDataFiles() {
  if (this->IsCommitted) return;
  std::error_code ec;
  for (const auto& [name, staged] : this->Claimed) fs::remove(this->Folder / staged, ec);
}

void SceneDataFiles::RemoveInterruptedSaves(const std::string& subfolder) const {
  // A save killed between its two commits left a scene file naming temporary files: keep those.
  std::set<std::string> keep;
  for (const std::string& name : this->Owned) {
    const fs::path path(name);
    if (path.parent_path() == fs::path(subfolder)) keep.insert(path.filename().string());
  }
  RemoveStaleTemporaryFiles((this->Folder / subfolder).string(), keep);
}

std::string SceneDataFiles::Claim(const std::string& subfolder, const std::string& stem, const std::string& extension) {
  for (int n = 1;; ++n) {
    const std::string name = Join(subfolder, stem + (n > 1 ? "_" + std::to_string(n) : "") + extension);
    if (this->Claimed.count(name)) continue;
    std::error_code ec;
    // symlink_status: a dangling link is someone's file too.
    if (!this->Owned.count(name) && fs::exists(fs::symlink_status(this->Folder / name, ec))) continue;
    const fs::path path(name);
    this->Claimed[name] = Join(path.parent_path().string(),
                               fs::path(TemporaryPathFor("staged-" + path.filename().string())).string());
    return name;
  }
}

std::string SceneDataFiles::StagingPath(const std::string& name) const {
  const auto it = this->Claimed.find(name);
  return it == this->Claimed.end() ? std::string() : (this->Folder / it->second).string();
}

void SceneDataFiles::Drop(const std::string& name) {
  const auto it = this->Claimed.find(name);
  if (it == this->Claimed.end()) return;
  std::error_code ec;
  fs::remove(this->Folder / it->second, ec);
  this->Claimed.erase(it);
}

bool SceneDataFiles::Commit(const std::string& sceneFile, const SceneText& text, std::string& error) {
  // 1. The new scene, naming the temporary files; it owns the files it is about to replace or
  //    remove, so that a save killed from here on leaves them to the next save of this scene.
  std::set<std::string> alsoOwned = this->Owned;
  std::map<std::string, std::string> staged, final;
  for (const auto& [name, temporary] : this->Claimed) {
    staged[name] = temporary;
    final[name] = name;
    alsoOwned.insert(name);
  }
  if (!WriteFileAtomically(sceneFile, text(staged, {alsoOwned.begin(), alsoOwned.end()}), error)) return false;
  this->IsCommitted = true;
  // 2. The previous scene's files this one does not name (never the scene file, whatever it listed).
  std::error_code ec;
  const fs::path sceneName = fs::path(sceneFile).filename();
  for (const std::string& name : this->Owned)
    if (!this->Claimed.count(name) && fs::path(name) != sceneName) fs::remove(this->Folder / name, ec);
  // 3. The final names, each replaced at once by its new content.
  for (const auto& [name, temporary] : this->Claimed) {
    if (!ReplaceWithLinkTo((this->Folder / name).string(), (this->Folder / temporary).string(), error)) {
      error = "the scene was saved whole, but its data files keep their temporary names: " + error;
      return false;
    }
  }
  // 4. The scene naming them, owning nothing else.
  if (!WriteFileAtomically(sceneFile, text(final, {}), error)) {
    error = "the scene was saved whole, but its data files keep their temporary names: " + error;
    return false;
  }
  // 5. The temporary files (a kill before this leaves them to RemoveStaleTemporaryFiles).
  for (const auto& [name, temporary] : this->Claimed) fs::remove(this->Folder / temporary, ec);
  return true;
}

}  // namespace rp
