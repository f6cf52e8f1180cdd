#include "rpIgtlProtocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rp {
namespace igtl {

namespace {
struct Crc64Table {
  uint64_t Values[256];
  constexpr Crc64Table() : Values() {
    for (int i = 0; i < 256; ++i) {
      uint64_t c = static_cast<uint64_t>(i) << 56;
      for (int k = 0; k < 8; ++k) c = (c & 0x8000000000000000ull) ? (c << 1) ^ 0x42F0E1EBA9EA3693ull : (c << 1);
      Values[i] = c;
    }
  }
};
constexpr Crc64Table kTable;

uint16_t U16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
uint32_t U32(const uint8_t* p) {
  return (static_cast<uint32_t>(p[0]) << 24) | (static_cast<uint32_t>(p[1]) << 16) | (static_cast<uint32_t>(p[2]) << 8) | p[3];
}
uint64_t U64(const uint8_t* p) { return (static_cast<uint64_t>(U32(p)) << 32) | U32(p + 4); }
float F32(const uint8_t* p) {
  const uint32_t bits = U32(p);
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}
void Put16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v);
}
void Put32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}
void Put64(uint8_t* p, uint64_t v) {
  Put32(p, static_cast<uint32_t>(v >> 32));
  Put32(p + 4, static_cast<uint32_t>(v));
}
void PutF32(uint8_t* p, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  Put32(p, bits);
}
void CopyName(char* out, const uint8_t* in, size_t size) {
  std::memcpy(out, in, size);
  out[size] = '\0';
}
void QuaternionFromXyzw(const uint8_t* p, double q[4]) {
  q[1] = F32(p);
  q[2] = F32(p + 4);
  q[3] = F32(p + 8);
  q[0] = F32(p + 12);
}
}  // namespace

uint64_t Crc64(const void* data, size_t length, uint64_t crc) noexcept {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < length; ++i) crc = kTable.Values[((crc >> 56) ^ p[i]) & 0xFF] ^ (crc << 8);
  return crc;
}

const char* StatusName(Status status) noexcept {
  switch (status) {
    case Status::Ok: return "ok";
    case Status::Truncated: return "truncated message";
    case Status::BadHeader: return "malformed header";
    case Status::Oversized: return "oversized message";
    case Status::BadCrc: return "CRC mismatch";
    case Status::BadBody: return "malformed body";
    case Status::BadMetadata: return "malformed v3 metadata";
  }
  return "unknown";
}

bool Header::Is(const char* type) const { return std::strcmp(this->Type, type) == 0; }

Status ParseHeader(const uint8_t* data, Header& h, uint64_t maxBodySize) noexcept {
  h.Version = U16(data);
  CopyName(h.Type, data + 2, 12);
  CopyName(h.DeviceName, data + 14, 20);
  h.Timestamp = U64(data + 34);
  h.BodySize = U64(data + 42);
  h.Crc = U64(data + 50);
  if (h.Version < 1 || h.Version > 3) return Status::BadHeader;
  // A type is printable ASCII, NUL padded; anything else means we lost the message boundary.
  if (h.Type[0] == '\0') return Status::BadHeader;
  bool ended = false;
  for (int i = 0; i < 12; ++i) {
    const unsigned char c = static_cast<unsigned char>(data[2 + i]);
    if (c == 0) ended = true;
    else if (ended || c < 0x20 || c > 0x7E) return Status::BadHeader;
  }
  if (h.BodySize > maxBodySize) return Status::Oversized;
  return Status::Ok;
}

void WriteHeader(uint8_t* out, const Header& h) noexcept {
  Put16(out, h.Version);
  std::memset(out + 2, 0, 32);
  std::memcpy(out + 2, h.Type, strnlen(h.Type, 12));
  std::memcpy(out + 14, h.DeviceName, strnlen(h.DeviceName, 20));
  Put64(out + 34, h.Timestamp);
  Put64(out + 42, h.BodySize);
  Put64(out + 50, h.Crc);
}

uint64_t ToIgtlTimestamp(double seconds) noexcept {
  const double whole = std::floor(seconds);
  const uint64_t fraction = static_cast<uint64_t>((seconds - whole) * 4294967296.0);
  return (static_cast<uint64_t>(whole) << 32) | (fraction & 0xFFFFFFFFull);
}

const char* Body::Find(const char* key, uint32_t& valueSize) const noexcept {
  const size_t keyLength = std::strlen(key);
  for (int i = 0; i < this->MetaCount; ++i) {
    if (this->Meta[i].KeySize == keyLength && std::memcmp(this->Meta[i].Key, key, keyLength) == 0) {
      valueSize = this->Meta[i].ValueSize;
      return this->Meta[i].Value;
    }
  }
  valueSize = 0;
  return nullptr;
}

Status SplitBody(const Header& h, const uint8_t* body, Body& out) noexcept {
  out = Body{};
  out.Content = body;
  out.ContentSize = h.BodySize;
  if (h.Version < 2) return Status::Ok;
  if (h.BodySize < 12) return Status::BadMetadata;
  const uint16_t extSize = U16(body);
  const uint16_t metaHeaderSize = U16(body + 2);
  const uint32_t metaSize = U32(body + 4);
  out.MessageId = U32(body + 8);
  if (extSize < 12 || static_cast<uint64_t>(extSize) + metaHeaderSize + metaSize > h.BodySize) return Status::BadMetadata;
  out.Content = body + extSize;
  out.ContentSize = h.BodySize - extSize - metaHeaderSize - metaSize;
  if (metaHeaderSize == 0) return metaSize == 0 ? Status::Ok : Status::BadMetadata;
  const uint8_t* mh = out.Content + out.ContentSize;
  if (metaHeaderSize < 2) return Status::BadMetadata;
  const uint16_t count = U16(mh);
  if (metaHeaderSize != 2u + 8u * count) return Status::BadMetadata;
  const uint8_t* data = mh + metaHeaderSize;
  uint64_t used = 0;
  for (uint16_t i = 0; i < count; ++i) {
    const uint8_t* item = mh + 2 + 8 * i;
    const uint16_t keySize = U16(item);
    const uint32_t valueSize = U32(item + 4);
    if (used + keySize + valueSize > metaSize) return Status::BadMetadata;
    if (out.MetaCount < Body::Capacity) {
      MetaItem& m = out.Meta[out.MetaCount++];
      m.Key = reinterpret_cast<const char*>(data + used);
      m.KeySize = keySize;
      m.Value = reinterpret_cast<const char*>(data + used + keySize);
      m.ValueSize = valueSize;
    }
    used += keySize + valueSize;
  }
  return used == metaSize ? Status::Ok : Status::BadMetadata;
}

Status DecodeTransform(const uint8_t* c, size_t size, double m[16]) noexcept {
  if (size != 48) return Status::BadBody;
  // Column-major rotation (R11 R21 R31 R12 ...) then translation.
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) m[4 * row + col] = F32(c + 4 * (3 * col + row));
  for (int row = 0; row < 3; ++row) m[4 * row + 3] = F32(c + 36 + 4 * row);
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
  for (int i = 0; i < 12; ++i)
    if (!std::isfinite(m[i])) return Status::BadBody;
  return Status::Ok;
}

Status DecodePosition(const uint8_t* c, size_t size, double position[3], double q[4]) noexcept {
  if (size != 12 && size != 24 && size != 28) return Status::BadBody;
  for (int k = 0; k < 3; ++k) position[k] = F32(c + 4 * k);
  q[0] = 1;
  q[1] = q[2] = q[3] = 0;
  if (size >= 24) {
    q[1] = F32(c + 12);
    q[2] = F32(c + 16);
    q[3] = F32(c + 20);
    const double xyz = q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    q[0] = size == 28 ? F32(c + 24) : std::sqrt(std::max(0.0, 1.0 - xyz));
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 0.5 && n < 1.5)) return Status::BadBody;  // not a rotation (also catches NaN)
  for (int k = 0; k < 4; ++k) q[k] /= n;
  return Status::Ok;
}

Status CountElements(size_t size, size_t elementSize, int& count) noexcept {
  count = 0;
  if (size % elementSize != 0) return Status::BadBody;
  count = static_cast<int>(size / elementSize);
  return Status::Ok;
}

void DecodeTDataElement(const uint8_t* e, TrackingElement& out) noexcept {
  CopyName(out.Name, e, 20);
  out.Type = e[20];
  DecodeTransform(e + 22, 48, out.Matrix);
}

void DecodeQtDataElement(const uint8_t* e, TrackingElement& out) noexcept {
  CopyName(out.Name, e, 20);
  out.Type = e[20];
  for (int k = 0; k < 3; ++k) out.Position[k] = F32(e + 22 + 4 * k);
  QuaternionFromXyzw(e + 34, out.Quaternion);
}

Status DecodeStatus(const uint8_t* c, size_t size, int& code, char errorName[21]) noexcept {
  if (size < 30) return Status::BadBody;
  code = U16(c);
  CopyName(errorName, c + 10, 20);
  return Status::Ok;
}

std::vector<uint8_t> BuildMessage(uint16_t version, const char* type, const char* deviceName, double timestamp,
                                  const uint8_t* content, size_t contentSize,
                                  const std::vector<std::pair<std::string, std::string>>& metadata, uint32_t messageId) {
  std::vector<uint8_t> body;
  if (version >= 2) {
    size_t metaSize = 0;
    for (const auto& kv : metadata) metaSize += kv.first.size() + kv.second.size();
    const size_t metaHeaderSize = metadata.empty() ? 0 : 2 + 8 * metadata.size();
    body.resize(12 + contentSize + metaHeaderSize + metaSize);
    Put16(&body[0], 12);
    Put16(&body[2], static_cast<uint16_t>(metaHeaderSize));
    Put32(&body[4], static_cast<uint32_t>(metaSize));
    Put32(&body[8], messageId);
    if (contentSize) std::memcpy(&body[12], content, contentSize);
    size_t at = 12 + contentSize;
    if (!metadata.empty()) {
      Put16(&body[at], static_cast<uint16_t>(metadata.size()));
      at += 2;
      for (const auto& kv : metadata) {
        Put16(&body[at], static_cast<uint16_t>(kv.first.size()));
        Put16(&body[at + 2], 3);  // US-ASCII
        Put32(&body[at + 4], static_cast<uint32_t>(kv.second.size()));
        at += 8;
      }
      for (const auto& kv : metadata) {
        std::memcpy(&body[at], kv.first.data(), kv.first.size());
        at += kv.first.size();
        std::memcpy(&body[at], kv.second.data(), kv.second.size());
        at += kv.second.size();
      }
    }
  } else {
    body.assign(content, content + contentSize);
  }
  Header h;
  h.Version = version;
  std::strncpy(h.Type, type, 12);
  std::strncpy(h.DeviceName, deviceName, 20);
  h.Timestamp = ToIgtlTimestamp(timestamp);
  h.BodySize = body.size();
  h.Crc = Crc64(body.data(), body.size());
  std::vector<uint8_t> message(HeaderSize + body.size());
  WriteHeader(message.data(), h);
  if (!body.empty()) std::memcpy(&message[HeaderSize], body.data(), body.size());
  return message;
}

std::vector<uint8_t> EncodeTransform(const double m[16]) {
  std::vector<uint8_t> c(48);
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) PutF32(&c[4 * (3 * col + row)], m[4 * row + col]);
  for (int row = 0; row < 3; ++row) PutF32(&c[36 + 4 * row], m[4 * row + 3]);
  return c;
}

}  // namespace igtl
}  // namespace rp
