#pragma once
// The numbered entries of a /proc directory (process ids in /proc, thread ids in
// /proc/<pid>/task): the one walk the CPU pinning and the CPU shield share.
#include <dirent.h>
#include <sys/types.h>

#include <cstdlib>

namespace rp {

/// Calls visit(id) for each entry of `path` whose name is a positive number; nothing when the
/// directory cannot be opened.
template <typename Visit>
void ForEachProcEntry(const char* path, Visit&& visit) {
  DIR* dir = opendir(path);
  if (!dir) return;
  while (const dirent* entry = readdir(dir)) {
    char* end = nullptr;
    const long id = std::strtol(entry->d_name, &end, 10);
    if (end != entry->d_name && *end == '\0' && id > 0) visit(static_cast<pid_t>(id));
  }
  closedir(dir);
}

}  // namespace rp
