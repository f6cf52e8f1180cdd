#pragma once
// A full disk on demand: in a child process (the mount vanishes with it and its private mount
// namespace), a tmpfs of `kilobytes` mounted on `dir`. As root directly; otherwise in a user
// namespace that maps us to root there. "" on success, else why not (the caller skips, saying so).
#include <sched.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace rptest {

inline std::string MountTinyTmpfs(const std::filesystem::path& dir, int kilobytes) {
  if (unshare(CLONE_NEWNS) != 0) {
    const uid_t uid = getuid();
    const gid_t gid = getgid();
    if (unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) return std::string("unshare: ") + std::strerror(errno);
    std::ofstream("/proc/self/setgroups") << "deny";
    std::ofstream("/proc/self/uid_map") << "0 " << uid << " 1";
    std::ofstream("/proc/self/gid_map") << "0 " << gid << " 1";
  }
  if (mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) return std::string("making mounts private: ") + std::strerror(errno);
  const std::string options = "size=" + std::to_string(kilobytes) + "k";
  if (mount("tmpfs", dir.c_str(), "tmpfs", 0, options.c_str()) != 0) return std::string("mount -t tmpfs: ") + std::strerror(errno);
  return "";
}

}  // namespace rptest
