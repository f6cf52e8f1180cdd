// libFuzzer target: tool definition JSON (Resources/Tools/*.json) on arbitrary bytes, and the
// NDI .rom checks on the same bytes. A bad definition may only throw std::runtime_error.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rpToolDefinition.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const rp::ToolDefinition tool =
        rp::ParseToolDefinition(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    double m[16];
    rp::EvaluateTrajectory(tool, 1.25, m);
  } catch (const std::runtime_error&) {
  }
  const std::vector<uint8_t> bytes(data, data + size);
  std::string error;
  rp::rom::Validate(bytes, error);
  rp::rom::PartNumber(bytes);
  rp::rom::MarkerCount(bytes);
  return 0;
}
