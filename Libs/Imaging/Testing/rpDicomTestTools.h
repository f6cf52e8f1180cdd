#pragma once
// Shared by the DICOM tests: find the packages' command-line tools (gdcmconv, dcmcjpeg, dcmodify...)
// and run them on copies of the real series in shared/data.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace rp::testing {

/// The tool's path on PATH, or "" when it is not installed.
inline std::string FindTool(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0)
      return candidate.string();
  }
  return "";
}

/// Runs `tool arguments...` (each argument quoted), its output appended to `log`; the exit code.
inline int RunTool(const std::string& tool, const std::vector<std::string>& arguments, const std::string& log) {
  std::string command = "\"" + tool + "\"";
  for (const std::string& a : arguments) command += " '" + a + "'";
  command += " >>\"" + log + "\" 2>&1";
  return std::system(command.c_str());
}

/// The .dcm files of a folder in natural order (slice2 before slice10), at most `max`.
inline std::vector<std::filesystem::path> DicomFiles(const std::filesystem::path& folder, size_t max = 100000) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    if (e.path().extension() == ".dcm") files.push_back(e.path());
  std::sort(files.begin(), files.end(), [](const std::filesystem::path& a, const std::filesystem::path& b) {
    const std::string x = a.filename().string(), y = b.filename().string();
    return x.size() != y.size() ? x.size() < y.size() : x < y;
  });
  if (files.size() > max) files.resize(max);
  return files;
}

/// A fresh, empty folder under this test's output directory.
inline std::filesystem::path Scratch(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace rp::testing
