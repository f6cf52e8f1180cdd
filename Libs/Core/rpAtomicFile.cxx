#include "rpAtomicFile.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace rp {
namespace {
std::string TempPathFor(const std::string& path) {
  // Keep the extension last so writers that pick a format by extension still recognise it.
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + ".tmp-" + std::to_string(::getpid()) + "-" + base;
}

void SyncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}
}  // namespace

bool WriteAtomicallyWith(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& writer,
                         std::string& error) {
  const std::string temp = TempPathFor(path);
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
  return true;
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
