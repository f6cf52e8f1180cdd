#include "rpNrrdGzipVoxels.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <memory>
#include <vector>

#include <libdeflate.h>

#include "rpStrings.h"

namespace rp {
namespace {

bool LittleEndianHost() {
  const unsigned short one = 1;
  return *reinterpret_cast<const unsigned char*>(&one) == 1;
}

}  // namespace

bool ReadNrrdGzipVoxels(const std::string& path, void* voxels, size_t bytes, size_t componentSize) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  // The header: "NRRD000n", then "field: value" lines (and "#" comments, "key:=value" pairs)
  // up to the first empty line; the data follows it.
  std::string line;
  if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0) return false;
  std::map<std::string, std::string> fields;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) break;
    if (line[0] == '#') continue;
    const size_t colon = line.find(": ");
    if (line.find(":=") < colon) continue;  // a key:=value pair
    if (colon == std::string::npos) return false;
    std::string name = line.substr(0, colon);
    name.erase(std::remove(name.begin(), name.end(), ' '), name.end());  // "data file" = "datafile"
    fields[name] = Trim(line.substr(colon + 2));
  }
  if (!in) return false;
  auto field = [&](const std::string& name) {
    const auto it = fields.find(name);
    return it == fields.end() ? std::string() : it->second;
  };
  const std::string encoding = field("encoding");
  if (encoding != "gzip" && encoding != "gz") return false;
  if (!field("datafile").empty()) return false;  // detached data
  for (const char* skip : {"lineskip", "byteskip"})
    if (!field(skip).empty() && field(skip) != "0") return false;
  if (componentSize > 1 && (field("endian") != "little" || !LittleEndianHost())) return false;

  const std::streamoff start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  if (start < 0 || end < start) return false;
  std::vector<char> compressed(static_cast<size_t>(end - start));
  in.seekg(start);
  if (!in.read(compressed.data(), static_cast<std::streamsize>(compressed.size()))) return false;
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!inflater) return false;
  // One gzip member as NRRD writers make it; members written one after another are read in turn.
  size_t used = 0, filled = 0;
  auto* out = static_cast<unsigned char*>(voxels);
  while (filled < bytes && used < compressed.size()) {
    size_t memberIn = 0, memberOut = 0;
    if (libdeflate_gzip_decompress_ex(inflater.get(), compressed.data() + used, compressed.size() - used,
                                      out + filled, bytes - filled, &memberIn, &memberOut) != LIBDEFLATE_SUCCESS)
      return false;
    used += memberIn, filled += memberOut;
  }
  return filled == bytes;
}

}  // namespace rp
