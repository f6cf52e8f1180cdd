// libFuzzer target: NDI reply framing and the TX, BX, PHSR and PHINF port-location parsers on arbitrary bytes.
// Built by Testing/Fuzz (clang sub-build); ctest -L fuzz runs it on its committed corpus.
#include <cstdint>
#include <cstring>
#include <memory>

#include "rpNdiProtocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rp::ndi;
  size_t offset = 0;
  // Walk the stream as the driver does: frame, parse, resynchronise on garbage.
  while (offset < size) {
    size_t length = 0;
    const ParseResult framing = FindFrame(data + offset, size - offset, length);
    if (framing.Code == ParseCode::Incomplete) break;
    if (!framing.Ok()) {
      ++offset;
      continue;
    }
    TrackingReply reply;
    ParseBx(data + offset, length, reply);
    ParseTx(data + offset, length, reply);
    const char* payload;
    size_t payloadLength;
    if (CheckAsciiReply(data + offset, length, payload, payloadLength).Ok()) {
      uint8_t handles[MaxHandles];
      int count;
      ParsePhsr(payload, payloadLength, handles, MaxHandles, count);
      PortLocation location;
      ParsePhinfPortLocation(payload, payloadLength, location);
    }
    offset += length;
  }
  return 0;
}
