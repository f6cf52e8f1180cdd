// libFuzzer target: NDI tool definition files (.rom, rpNdiRom: 752 bytes read field by field,
// checksum, marker count and coordinates checked) on arbitrary bytes; what reads is written
// back and must read again to the same part number and markers, byte for byte the same file.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "rpNdiRom.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rp::rom::Definition definition;
  std::string error;
  if (!rp::rom::Read(data, size, definition, error)) return 0;
  const std::vector<uint8_t> written = rp::rom::Write(definition);
  rp::rom::Definition again;
  if (!rp::rom::Read(written.data(), written.size(), again, error)) std::abort();
  if (again.PartNumber != definition.PartNumber || again.Markers != definition.Markers) std::abort();
  if (rp::rom::Write(again) != written) std::abort();
  return 0;
}
