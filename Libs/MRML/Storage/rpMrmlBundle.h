#pragma once
// The zip side of 3D Slicer's Medical Reality Bundle (.mrb), through Debian's libarchive (what
// Slicer's vtkArchive uses too): unpacking a bundle into a folder safely, finding its main scene,
// and packing a folder into a bundle. Unpacking checks every entry before writing any file: an
// entry that would land outside the folder (an absolute path, a `..` component), a link or a
// device, or declared sizes that add up to more than the limit (a zip bomb) refuse the whole
// bundle; the bytes actually written are counted against the same limit.
#include <cstdint>
#include <string>
#include <vector>

namespace rp {

/// Unpacks `zipPath` into the existing folder `folder`. `entries` receives the files' relative
/// paths. False with `error` naming the bundle and the problem.
bool UnpackBundle(const std::string& zipPath, const std::string& folder, uint64_t maxBytes,
                  std::vector<std::string>& entries, std::string& error);

/// The main scene of a bundle: the .mrml with the fewest folders above it (then the first by
/// name); "" when there is none.
std::string FindMainScene(const std::vector<std::string>& entries);

/// Writes a zip at `zipPath` holding the files under `folder`, as "<rootName>/<relative path>"
/// (Slicer's bundles keep the scene in one top folder).
bool PackBundle(const std::string& folder, const std::string& rootName, const std::string& zipPath,
                std::string& error);

/// A new empty folder in `parent` (default: the system's temporary folder), removed with its
/// contents when this object goes away.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix, const std::string& parent = "");
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& Path() const { return this->Folder; }  // "" when it could not be made
 private:
  std::string Folder;
};

}  // namespace rp
