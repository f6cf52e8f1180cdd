#include "rpAtomicFile.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rp {
namespace {
constexpr const char* TempPrefix = ".tmp-";

void SyncFile(const std::string& path, int flags = O_RDONLY) {
  const int fd = ::open(path.c_str(), flags);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// The rename itself reaches the disk only when the folder is synced.
void SyncFolderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  SyncFile(slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : path.substr(0, slash),
           O_RDONLY | O_DIRECTORY);
}
}  // namespace

std::string TemporaryPathFor(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + TempPrefix + std::to_string(::getpid()) + "-" + base;
}

bool WriteAtomicallyWith(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& writer,
                         std::string& error) {
  const std::string temp = TemporaryPathFor(path);
  std::string writerError;
  if (!writer(temp, writerError)) {
    std::remove(temp.c_str());
    error = "cannot write '" + path + "': " + (writerError.empty() ? "writer failed" : writerError);
    return false;
  }
  SyncFile(temp);
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    error = "cannot replace '" + path + "': " + std::strerror(errno);
    std::remove(temp.c_str());
    return false;
  }
  SyncFolderOf(path);
  return true;
}

bool ReplaceWithLinkTo(const std::string& path, const std::string& source, std::string& error) {
  return WriteAtomicallyWith(
      path,
      [&source](const std::string& temp, std::string& err) {
        std::error_code ec;
        std::filesystem::create_hard_link(source, temp, ec);
        if (!ec) return true;
        std::filesystem::copy_file(source, temp, std::filesystem::copy_options::overwrite_existing, ec);
        if (ec) err = "cannot link or copy '" + source + "': " + ec.message();
        return !ec;
      },
      error);
}

int RemoveStaleTemporaryFiles(const std::string& folder, const std::set<std::string>& keep) {
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(TempPrefix, 0) != 0 || keep.count(name)) continue;
    const size_t dash = name.find('-', std::strlen(TempPrefix));
    if (dash == std::string::npos) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + std::strlen(TempPrefix), &end, 10);
    if (end != name.c_str() + dash || pid <= 0) continue;
    // Alive (or not ours to judge): keep. Gone: its save can never finish.
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code removeError;
    if (std::filesystem::remove(entry.path(), removeError)) ++removed;
  }
  return removed;
}

bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string& error) {
  return WriteAtomicallyWith(
      path,
      [&contents](const std::string& temp, std::string& err) {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) {
          err = std::strerror(errno);
          return false;
        }
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.close();
        if (!out) {
          err = "write failed (disk full?)";
          return false;
        }
        return true;
      },
      error);
}

bool ReadFile(const std::string& path, std::string& contents, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  contents = ss.str();
  return true;
}

}  // namespace rp
