#include "rpDicomMagic.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace rp {

bool HasDicomMagic(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char header[132] = {};
  if (!file.read(header, sizeof header)) return false;
  return std::equal(header + 128, header + 132, "DICM");
}

bool MaybeDicomFile(const std::string& path) {
  if (HasDicomMagic(path)) return true;
  const std::string extension = std::filesystem::path(path).extension().string();
  return extension.empty() || extension == ".dcm" || extension == ".DCM";
}

}  // namespace rp
