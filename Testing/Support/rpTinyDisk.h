#pragma once
// A full disk on demand: in a child process (the mount vanishes with it and its private mount
// namespace), a tmpfs of `kilobytes` mounted on `dir`. As root directly; otherwise in a user
// namespace that maps us to root there. "" on success, else why not (the caller skips, saying so).
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
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

/// Runs `work` in a child process whose `dir` is a tmpfs of `kilobytes` and returns what it
/// returned; "skip\n<why>" when no such disk can be made here (the test then skips, saying why).
/// The child ends with _exit: it runs no destructor of the test process's objects.
inline std::string RunOnTinyDisk(const std::filesystem::path& dir, int kilobytes, const std::function<std::string()>& work) {
  int out[2];
  if (pipe(out) != 0) return "skip\npipe: " + std::string(std::strerror(errno));
  const pid_t child = fork();
  if (child < 0) return "skip\nfork: " + std::string(std::strerror(errno));
  if (child == 0) {
    close(out[0]);
    const std::string why = MountTinyTmpfs(dir, kilobytes);
    const std::string text = why.empty() ? work() : "skip\n" + why;
    (void)!write(out[1], text.data(), text.size());
    _exit(0);
  }
  close(out[1]);
  std::string result;
  char buffer[4096];
  for (ssize_t n; (n = read(out[0], buffer, sizeof buffer)) > 0;) result.append(buffer, static_cast<size_t>(n));
  close(out[0]);
  int status = 0;
  waitpid(child, &status, 0);
  return result;
}

}  // namespace rptest
