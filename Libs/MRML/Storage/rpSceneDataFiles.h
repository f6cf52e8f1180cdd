#pragma once
// The data files of a scene save, in a folder that may hold an earlier save of the same scene and
// files that belong to something else. What a scene file owns: the data files it names and the
// files it lists as its own (only a save that was interrupted lists any). Saving over it:
//  - each node keeps its name from one save to the next (CT.nrrd stays CT.nrrd, with the new
//    content), so scripts and users find the same files every time;
//  - a file the previous scene does not own is never written over: its name belongs to something
//    else and the node takes the next free one (CT_2.nrrd);
//  - the previous scene's files that the new one no longer names are removed, and nothing else.
// All or nothing, as before (rpSceneSaveFaultTest): the data go to temporary files first
// (".tmp-<pid>-staged-CT.nrrd"); the scene file is committed naming them, and listing the files it
// is about to replace as its own; each final name is then replaced by a link to its temporary
// file; the scene file is committed again naming the final names; the temporary files go. A save
// killed at any point leaves a scene file whose data are all there and all of one save, and that
// owns whatever that save left behind, so the next save finds the same names free.
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace rp {

class SceneDataFiles {
 public:
  /// `folder`: the scene file's folder. `owned`: what the scene file being replaced owns, relative
  /// to `folder` ('/'-separated); names that leave the folder are ignored.
  SceneDataFiles(std::filesystem::path folder, const std::set<std::string>& owned);
  /// Removes the temporary files of a save that did not commit.
  ~SceneDataFiles();
  SceneDataFiles(const SceneDataFiles&) = delete;
  SceneDataFiles& operator=(const SceneDataFiles&) = delete;

  /// Removes from `subfolder` ("" or e.g. "Data") the temporary files of saves that were killed,
  /// keeping those the previous scene file names.
  void RemoveInterruptedSaves(const std::string& subfolder) const;

  /// The name (relative to the folder) for a data file: `subfolder/stem + extension`, else with
  /// `_2`, `_3`... before the extension: the first not taken in this save that the previous scene
  /// owns or that is absent from the folder.
  std::string Claim(const std::string& subfolder, const std::string& stem, const std::string& extension);
  /// Where the data of a claimed name are written before the commit (a temporary file beside it).
  std::string StagingPath(const std::string& name) const;
  /// Forgets a claimed name whose data could not be written (its temporary file is removed).
  void Drop(const std::string& name);

  /// The text of the scene file, given how it names each claimed file (claimed name -> the name
  /// to write) and the other files it owns (to list as its own).
  using SceneText = std::function<std::string(const std::map<std::string, std::string>& names,
                                              const std::vector<std::string>& alsoOwned)>;
  /// Commits the save to `sceneFile` in the order above. False with `error`: when nothing was
  /// committed the previous scene is intact; when `Committed()` the scene file holds the new scene
  /// whole, but under the temporary names (`error` says why they could not be replaced).
  bool Commit(const std::string& sceneFile, const SceneText& text, std::string& error);
  bool Committed() const { return this->IsCommitted; }

  /// A name a scene may own: relative, inside its folder, no "." or ".." parts.
  static bool IsOwnable(const std::string& name);

 private:
  std::filesystem::path Folder;
  std::set<std::string> Owned;
  std::map<std::string, std::string> Claimed;  // claimed name -> its temporary file, relative
  bool IsCommitted = false;
};

}  // namespace rp
