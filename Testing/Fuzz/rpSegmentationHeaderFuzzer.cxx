// libFuzzer target: the segment table of a .seg.nrrd header on arbitrary bytes. The input is
// read as NRRD header lines ("key:=value" fields, as ITK's NRRD reader hands them over); the
// parser of our Segment<N>_* fields gets the resulting key/value map.
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rpSegmentationHeader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::map<std::string, std::string> fields;
  for (std::string line; std::getline(in, line);) {
    const auto separator = line.find(":=");
    if (separator != std::string::npos) fields[line.substr(0, separator)] = line.substr(separator + 2);
  }
  std::vector<rp::SegmentationHeaderSegment> segments;
  std::string error;
  rp::ParseSegmentationHeader("fuzz.seg.nrrd", fields, segments, error);
  return 0;
}
