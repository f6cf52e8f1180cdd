#pragma once
// Atomic file writes: write to a temporary file beside the target (".tmp-<pid>-<name>"), fsync,
// rename it over the target, fsync the folder; so a failed or interrupted save never destroys
// the last good file.
#include <functional>
#include <set>
#include <string>

namespace rp {

/// Writes `contents` to `path` atomically. Returns false and sets `error` on failure.
bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string& error);

/// Calls `writer(temporaryPath)` (which must create the file and return true on success), then
/// renames the temporary file over `path`. The temporary file is removed on failure.
bool WriteAtomicallyWith(const std::string& path,
                         const std::function<bool(const std::string& tempPath, std::string& error)>& writer,
                         std::string& error);

/// The temporary name this process writes `path` under before renaming it: ".tmp-<pid>-<name>"
/// beside it (the extension stays last, so writers that choose a format by it still do).
std::string TemporaryPathFor(const std::string& path);

/// Makes `path` hold what `source` holds, atomically: a hard link to `source` (a copy where the
/// file system has none) renamed over `path`. `source` stays.
bool ReplaceWithLinkTo(const std::string& path, const std::string& source, std::string& error);

/// Removes the temporary files of writers that died (killed mid-save) from `folder`: those whose
/// process no longer exists, except the file names in `keep` (a scene file still names them).
/// Returns how many were removed.
int RemoveStaleTemporaryFiles(const std::string& folder, const std::set<std::string>& keep = {});

/// Reads a whole file. Returns false and sets `error` naming the file on failure.
bool ReadFile(const std::string& path, std::string& contents, std::string& error);

}  // namespace rp
