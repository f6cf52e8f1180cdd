#include "rpRecordingFolder.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>


namespace rp {

namespace {
// "x.igs.mha" → ("x", ".igs.mha"); "x.mha" → ("x", ".mha"): PLUS's double extension kept whole.
void SplitExtension(const std::string& name, std::string& stem, std::string& extension) {
  size_t dot = name.rfind('.');
  if (dot != std::string::npos && dot > 0) {
    const size_t inner = name.rfind('.', dot - 1);
    if (inner != std::string::npos && inner > 0 && name.compare(inner, dot - inner, ".igs") == 0) dot = inner;
  }
  stem = dot == std::string::npos ? name : name.substr(0, dot);
  extension = dot == std::string::npos ? "" : name.substr(dot);
}

std::string DateTimeSuffix(std::time_t now) {
  std::tm local{};
  localtime_r(&now, &local);
  char text[32];
  std::strftime(text, sizeof text, "_%Y%m%d_%H%M%S", &local);  // PLUS's vtkPlusVirtualCapture naming
  return text;
}
}  // namespace

RecordingFolder::~RecordingFolder() {
  if (this->Fd >= 0) ::close(this->Fd);
}

bool RecordingFolder::Open(const std::string& path, std::string& error) {
  if (this->Fd >= 0) ::close(this->Fd);
  this->Fd = ::open(path.empty() ? "." : path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path.empty() ? "." : path, ec);
  this->Folder = ec ? path : absolute.lexically_normal().string();
  if (this->Fd < 0) {
    error = "recording folder " + this->Folder + ": " + std::strerror(errno);
    return false;
  }
  return true;
}

std::string RecordingFolder::CheckName(const std::string& name) {
  if (name.empty()) return "OutputFilename is empty";
  if (name[0] == '/') return "OutputFilename " + name + " is an absolute path: give a file name, written into the recording folder";
  if (name.find('\\') != std::string::npos || (name.size() > 1 && name[1] == ':'))
    return "OutputFilename " + name + " is a Windows path: give a file name, written into the recording folder";
  for (unsigned char c : name)
    if (c < 0x20 || c == 0x7F) return "OutputFilename holds a control character";
  if (name == ".." || name.rfind("../", 0) == 0 || name.find("/../") != std::string::npos ||
      (name.size() >= 3 && name.compare(name.size() - 3, 3, "/..") == 0))
    return "OutputFilename " + name + " has a '..' part: it would leave the recording folder";
  if (name.find('/') != std::string::npos) return "OutputFilename " + name + " names a folder: give a file name, written into the recording folder";
  if (name[0] == '.') return "OutputFilename " + name + " is hidden (starts with '.')";
  if (name.size() > NAME_MAX - 24) return "OutputFilename is longer than " + std::to_string(NAME_MAX - 24) + " characters";
  const std::string lower = [&] {
    std::string l = name;
    for (char& c : l) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return l;
  }();
  const auto endsWith = [&](const char* suffix) {
    const size_t n = std::strlen(suffix);
    return lower.size() > n && lower.compare(lower.size() - n, n, suffix) == 0;
  };
  if (!endsWith(".mha") && !endsWith(".nrrd"))
    return "OutputFilename " + name + " is not a PLUS sequence file (.igs.mha or .igs.nrrd)";
  return "";
}

bool RecordingFolder::Create(const std::string& requested, Created& created, std::string& error, std::time_t now) const {
  if (this->Fd < 0) {
    error = "no recording folder";
    return false;
  }
  error = CheckName(requested);
  if (!error.empty()) return false;
  struct stat st {};
  if (::fstatat(this->Fd, requested.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode)) {
    error = "OutputFilename " + requested + " is a symbolic link in the recording folder: refused";
    return false;
  }
  std::string stem, extension;
  SplitExtension(requested, stem, extension);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const std::string name = attempt == 0   ? requested
                             : attempt == 1 ? stem + DateTimeSuffix(now) + extension
                                            : stem + DateTimeSuffix(now) + "_" + std::to_string(attempt) + extension;
    // O_EXCL: never an existing file (nor a link, which O_EXCL does not follow); O_NOFOLLOW too.
    const int fd = ::openat(this->Fd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
      created = {fd, name, this->Folder + "/" + name, attempt > 0};
      return true;
    }
    if (errno != EEXIST) {
      error = "cannot create " + this->Folder + "/" + name + ": " + std::strerror(errno);
      return false;
    }
  }
  error = "cannot find a free name for " + requested + " in " + this->Folder;
  return false;
}

}  // namespace rp
