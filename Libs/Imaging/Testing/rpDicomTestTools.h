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

/// A packaged tool that re-encodes a DICOM file into one transfer syntax: `Tool Arguments in out`.
struct DicomEncoder {
  std::string Name, Tool, Arguments, Package, TransferSyntaxUID;
  std::string OnlySource;  // "" or the one source series it applies to (see Prepare)
  std::string Prepare;     // dcmodify arguments applied to the input first ("" = none)
};

/// Every encoder the tests and the Volumes benchmark use, one per syntax and tool.
inline const std::vector<DicomEncoder>& DicomEncoders() {
  static const std::vector<DicomEncoder> encoders = {
      {"implicit-little", "dcmconv", "+ti", "dcmtk", "1.2.840.10008.1.2", "", ""},
      {"explicit-little", "dcmconv", "+te", "dcmtk", "1.2.840.10008.1.2.1", "", ""},
      {"explicit-big", "dcmconv", "+tb", "dcmtk", "1.2.840.10008.1.2.2", "", ""},
      {"deflated-dcmconv", "dcmconv", "+td", "dcmtk", "1.2.840.10008.1.2.1.99", "", ""},
      {"deflated-gdcm", "gdcmconv", "--deflated", "libgdcm-tools", "1.2.840.10008.1.2.1.99", "", ""},
      {"raw-gdcm", "gdcmconv", "--raw -X", "libgdcm-tools", "1.2.840.10008.1.2.1", "", ""},
      {"rle-dcmcrle", "dcmcrle", "", "dcmtk", "1.2.840.10008.1.2.5", "", ""},
      {"rle-gdcm", "gdcmconv", "--rle", "libgdcm-tools", "1.2.840.10008.1.2.5", "", ""},
      {"jpeg-lossless-sv1", "dcmcjpeg", "+e1", "dcmtk", "1.2.840.10008.1.2.4.70", "", ""},
      {"jpeg-lossless-p14", "dcmcjpeg", "+el", "dcmtk", "1.2.840.10008.1.2.4.57", "", ""},
      {"jpeg-lossless-gdcm", "gdcmconv", "--jpeg", "libgdcm-tools", "1.2.840.10008.1.2.4.70", "", ""},
      {"jpeg-baseline", "dcmcjpeg", "+eb", "dcmtk", "1.2.840.10008.1.2.4.50", "", ""},
      {"jpeg-extended", "dcmcjpeg", "+ee", "dcmtk", "1.2.840.10008.1.2.4.51", "", ""},
      {"jpegls-lossless-dcmcjpls", "dcmcjpls", "", "dcmtk", "1.2.840.10008.1.2.4.80", "", ""},
      {"jpegls-lossless-gdcm", "gdcmconv", "--jpegls", "libgdcm-tools", "1.2.840.10008.1.2.4.80", "", ""},
      // DCMTK's encoder refuses near-lossless on signed pixels; the knee CT's stored values are
      // all >= 0 (HU = stored - 1024), so marking them unsigned (dcmodify) keeps every value.
      {"jpegls-near-dcmcjpls", "dcmcjpls", "+en +md 2", "dcmtk", "1.2.840.10008.1.2.4.81", "knee-ct",
       "-nb -m \"(0028,0103)=0\""},
      {"jpegls-near-gdcm", "gdcmconv", "--jpegls --lossy -e 3", "libgdcm-tools", "1.2.840.10008.1.2.4.81", "", ""},
      {"j2k-lossless", "gdcmconv", "--j2k", "libgdcm-tools", "1.2.840.10008.1.2.4.90", "", ""},
      {"j2k-lossy", "gdcmconv", "--j2k --lossy -q 80", "libgdcm-tools", "1.2.840.10008.1.2.4.91", "", ""},
  };
  return encoders;
}

/// Re-encodes `in` into `out` with `encoder` (output appended to `log`); the exit code.
inline int Encode(const DicomEncoder& encoder, const std::string& tool, const std::string& in, const std::string& out,
                  const std::string& log) {
  const std::string command = "\"" + tool + "\" " + encoder.Arguments + " \"" + in + "\" \"" + out + "\" >>\"" + log + "\" 2>&1";
  return std::system(command.c_str());
}

/// A fresh, empty folder under this test's output directory.
#ifdef ROBOPLAN_TEST_OUTPUT_DIR
inline std::filesystem::path Scratch(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
#endif

}  // namespace rp::testing
