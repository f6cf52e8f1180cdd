// libFuzzer target: OpenIGTLink header, v3 extended header/metadata and every body we read on
// arbitrary bytes (CRC not required, so the fuzzer reaches the body decoders).
#include <cstdint>
#include <cstring>

#include "rpIgtlProtocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rp::igtl;
  size_t offset = 0;
  while (size - offset >= HeaderSize) {
    Header h;
    const Status status = ParseHeader(data + offset, h, 1u << 20);
    if (status != Status::Ok) return 0;
    if (h.BodySize > size - offset - HeaderSize) return 0;
    const uint8_t* body = data + offset + HeaderSize;
    Crc64(body, h.BodySize);
    Body split;
    if (SplitBody(h, body, split) == Status::Ok) {
      uint32_t n;
      split.Find("IGTL_DEVICE_NAME", n);
      double m[16], p[3], q[4];
      DecodeTransform(split.Content, split.ContentSize, m);
      DecodePosition(split.Content, split.ContentSize, p, q);
      int count;
      TrackingElement e;
      if (CountElements(split.ContentSize, 70, count) == Status::Ok)
        for (int i = 0; i < count; ++i) DecodeTDataElement(split.Content + 70 * i, e);
      if (CountElements(split.ContentSize, 50, count) == Status::Ok)
        for (int i = 0; i < count; ++i) DecodeQtDataElement(split.Content + 50 * i, e);
      int code;
      char name[21];
      DecodeStatus(split.Content, split.ContentSize, code, name);
      uint16_t encoding;
      const char* text;
      size_t length;
      DecodeString(split.Content, split.ContentSize, encoding, text, length);
      uint32_t commandId;
      char commandName[CommandNameSize + 1];
      DecodeCommand(split.Content, split.ContentSize, commandId, commandName, text, length);  // COMMAND / RTS_COMMAND
      int32_t resolution;
      char coordinate[33];
      DecodeStartTracking(split.Content, split.ContentSize, resolution, coordinate);
      DecodeRts(split.Content, split.ContentSize, code);
      ImageHeader image;
      const uint8_t* pixels;
      if (DecodeImage(split.Content, split.ContentSize, image, pixels) == Status::Ok) {
        double ijkToRas[16];
        image.IjkToRas(ijkToRas);
      }
    }
    offset += HeaderSize + h.BodySize;
  }
  return 0;
}
