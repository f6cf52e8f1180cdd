#include "rpIgtlProtocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rpLPSRAS.h"

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
// A NUL-padded fixed-size name field (truncated when longer).
void PutName(uint8_t* out, const char* name, size_t size) {
  std::memset(out, 0, size);
  std::memcpy(out, name, strnlen(name, size));
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
  if (size != TransformSize) return Status::BadBody;
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
  if (size < StatusHeaderSize) return Status::BadBody;
  code = U16(c);
  CopyName(errorName, c + 10, 20);
  return Status::Ok;
}

Status DecodeString(const uint8_t* c, size_t size, uint16_t& encoding, const char*& text, size_t& length) noexcept {
  if (size < StringHeaderSize) return Status::BadBody;
  encoding = U16(c);
  length = U16(c + 2);
  if (StringHeaderSize + length > size) return Status::BadBody;
  text = reinterpret_cast<const char*>(c + StringHeaderSize);
  return Status::Ok;
}

Status DecodeCommand(const uint8_t* c, size_t size, uint32_t& id, char name[CommandNameSize + 1], const char*& text,
                     size_t& length) noexcept {
  name[0] = '\0';
  if (size < CommandHeaderSize) return Status::BadBody;
  id = U32(c);
  CopyName(name, c + 4, CommandNameSize);
  length = U32(c + 4 + CommandNameSize + 2);
  if (length > size - CommandHeaderSize) return Status::BadBody;
  text = reinterpret_cast<const char*>(c + CommandHeaderSize);
  return Status::Ok;
}

Status DecodeStartTracking(const uint8_t* c, size_t size, int32_t& resolutionMs, char coordinateName[33]) noexcept {
  resolutionMs = 0;
  coordinateName[0] = '\0';
  if (size < 4) return Status::BadBody;
  resolutionMs = static_cast<int32_t>(U32(c));
  if (size >= StartTrackingSize) CopyName(coordinateName, c + 4, 32);
  return Status::Ok;
}

Status DecodeRts(const uint8_t* c, size_t size, int& status) noexcept {
  status = -1;
  if (size < RtsSize) return Status::BadBody;
  status = static_cast<int8_t>(c[0]);
  return Status::Ok;
}

size_t ImageHeader::ScalarBytes(uint8_t type) noexcept {
  switch (type) {
    case Int8: case UInt8: return 1;
    case Int16: case UInt16: return 2;
    case Int32: case UInt32: case Float32: return 4;
    case Float64: return 8;
  }
  return 0;
}

uint64_t ImageHeader::DataBytes() const noexcept {
  return static_cast<uint64_t>(this->SubSize[0]) * this->SubSize[1] * this->SubSize[2] * this->Components *
         ScalarBytes(this->ScalarType);
}

bool ImageHeader::IsWholeImage() const noexcept {
  for (int k = 0; k < 3; ++k)
    if (this->SubOffset[k] != 0 || this->SubSize[k] != this->Size[k]) return false;
  return true;
}

void ImageHeader::IjkToRas(double m[16]) const noexcept {
  for (int r = 0; r < 3; ++r) {
    double centre = this->Matrix[9 + r];
    for (int axis = 0; axis < 3; ++axis) {
      const double column = this->Matrix[3 * axis + r];  // direction * spacing of index axis
      m[4 * r + axis] = column;
      centre -= column * 0.5 * (static_cast<double>(this->Size[axis]) - 1.0);
    }
    m[4 * r + 3] = centre;
  }
  if (this->Coordinate == LPS) FlipLPSRASIndexToSpace(m);
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
}

Status DecodeImage(const uint8_t* c, size_t size, ImageHeader& h, const uint8_t*& pixels) noexcept {
  pixels = nullptr;
  if (size < ImageHeaderSize) return Status::BadBody;
  h.Version = U16(c);
  h.Components = c[2];
  h.ScalarType = c[3];
  h.Endian = c[4];
  h.Coordinate = c[5];
  for (int k = 0; k < 3; ++k) h.Size[k] = U16(c + 6 + 2 * k);
  for (int k = 0; k < 12; ++k) h.Matrix[k] = F32(c + 12 + 4 * k);
  for (int k = 0; k < 3; ++k) h.SubOffset[k] = U16(c + 60 + 2 * k);
  for (int k = 0; k < 3; ++k) h.SubSize[k] = U16(c + 66 + 2 * k);
  if (h.Version != 1 || h.Components == 0 || ImageHeader::ScalarBytes(h.ScalarType) == 0) return Status::BadBody;
  if ((h.Endian != ImageHeader::BigEndian && h.Endian != ImageHeader::LittleEndian) ||
      (h.Coordinate != ImageHeader::RAS && h.Coordinate != ImageHeader::LPS))
    return Status::BadBody;
  for (int k = 0; k < 3; ++k)
    if (h.Size[k] == 0 || h.SubSize[k] == 0 || h.SubOffset[k] + h.SubSize[k] > h.Size[k]) return Status::BadBody;
  for (int axis = 0; axis < 3; ++axis) {
    double length = 0;
    for (int r = 0; r < 3; ++r) length += static_cast<double>(h.Matrix[3 * axis + r]) * h.Matrix[3 * axis + r];
    if (!(length > 1e-12) || !std::isfinite(length)) return Status::BadBody;  // no spacing, or NaN
  }
  for (int k = 9; k < 12; ++k)
    if (!std::isfinite(h.Matrix[k])) return Status::BadBody;
  if (h.DataBytes() != size - ImageHeaderSize) return Status::BadBody;
  pixels = c + ImageHeaderSize;
  return Status::Ok;
}

// ---------------------------------------------------------------- encoders

void EncodeTransform(const double m[16], uint8_t out[TransformSize]) noexcept {
  // Column-major rotation (R11 R21 R31 R12 ...) then translation.
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) PutF32(out + 4 * (3 * col + row), m[4 * row + col]);
  for (int row = 0; row < 3; ++row) PutF32(out + 36 + 4 * row, m[4 * row + 3]);
}

void EncodePosition(const double p[3], const double q[4], uint8_t out[PositionSize]) noexcept {
  for (int k = 0; k < 3; ++k) PutF32(out + 4 * k, p[k]);
  for (int k = 0; k < 3; ++k) PutF32(out + 12 + 4 * k, q[k + 1]);
  PutF32(out + 24, q[0]);
}

void EncodeTDataElement(const char* name, uint8_t type, const double m[16], uint8_t out[TDataElementSize]) noexcept {
  PutName(out, name, NameSize);
  out[20] = type;
  out[21] = 0;
  EncodeTransform(m, out + 22);
}

void EncodeQtDataElement(const char* name, uint8_t type, const double p[3], const double q[4],
                         uint8_t out[QtDataElementSize]) noexcept {
  PutName(out, name, NameSize);
  out[20] = type;
  out[21] = 0;
  EncodePosition(p, q, out + 22);
}

size_t StatusSize(const char* statusString) noexcept { return StatusHeaderSize + std::strlen(statusString) + 1; }

void EncodeStatus(int code, int64_t subCode, const char* errorName, const char* statusString, uint8_t* out) noexcept {
  Put16(out, static_cast<uint16_t>(code));
  Put64(out + 2, static_cast<uint64_t>(subCode));
  PutName(out + 10, errorName, 20);
  const size_t n = std::strlen(statusString);
  std::memcpy(out + StatusHeaderSize, statusString, n + 1);
}

void EncodeStartTracking(int32_t resolutionMs, const char* coordinateName, uint8_t out[StartTrackingSize]) noexcept {
  Put32(out, static_cast<uint32_t>(resolutionMs));
  PutName(out + 4, coordinateName, 32);
}

void EncodeRts(int status, uint8_t out[RtsSize]) noexcept { out[0] = static_cast<uint8_t>(static_cast<int8_t>(status)); }

void EncodeString(const char* text, size_t length, uint8_t* out) noexcept {
  Put16(out, 3);  // US-ASCII (IANA MIBenum)
  Put16(out + 2, static_cast<uint16_t>(length));
  std::memcpy(out + StringHeaderSize, text, length);
}

void EncodeCommand(uint32_t id, const char* name, const char* text, size_t length, uint8_t* out) noexcept {
  Put32(out, id);
  std::memset(out + 4, 0, CommandNameSize);
  std::memcpy(out + 4, name, std::min(std::strlen(name), CommandNameSize));
  Put16(out + 4 + CommandNameSize, 3);  // US-ASCII (IANA MIBenum)
  Put32(out + 4 + CommandNameSize + 2, static_cast<uint32_t>(length));
  std::memcpy(out + CommandHeaderSize, text, length);
}

void EncodeImage(const ImageHeader& h, const uint8_t* pixels, uint8_t* out) noexcept {
  Put16(out, h.Version);
  out[2] = h.Components;
  out[3] = h.ScalarType;
  out[4] = h.Endian;
  out[5] = h.Coordinate;
  for (int k = 0; k < 3; ++k) Put16(out + 6 + 2 * k, h.Size[k]);
  for (int k = 0; k < 12; ++k) PutF32(out + 12 + 4 * k, h.Matrix[k]);
  for (int k = 0; k < 3; ++k) Put16(out + 60 + 2 * k, h.SubOffset[k]);
  for (int k = 0; k < 3; ++k) Put16(out + 66 + 2 * k, h.SubSize[k]);
  std::memcpy(out + ImageHeaderSize, pixels, static_cast<size_t>(h.DataBytes()));
}

// ---------------------------------------------------------------- framing

uint8_t* MessageWriter::Begin(uint16_t version, const char* type, const char* deviceName, double timestamp,
                              size_t contentSize, uint32_t messageId) {
  this->Pending = Header{};
  this->Pending.Version = version >= 2 ? 2 : 1;
  std::strncpy(this->Pending.Type, type, 12);
  std::strncpy(this->Pending.DeviceName, deviceName, 20);
  this->Pending.Timestamp = ToIgtlTimestamp(timestamp);
  this->ContentSize = contentSize;
  this->MessageId = messageId;
  const size_t need = HeaderSize + (this->Pending.Version >= 2 ? ExtendedHeaderSize + 2 : 0) + contentSize;
  if (this->Buffer.size() < need) this->Buffer.resize(need);
  this->Used = 0;
  return this->Buffer.data() + HeaderSize + (this->Pending.Version >= 2 ? ExtendedHeaderSize : 0);
}

void MessageWriter::Finish(const MetaPair* metadata, size_t count) {
  size_t body = this->ContentSize;
  if (this->Pending.Version >= 2) {
    size_t metaSize = 0;
    for (size_t i = 0; i < count; ++i) metaSize += std::strlen(metadata[i].Key) + std::strlen(metadata[i].Value);
    const size_t metaHeaderSize = 2 + 8 * count;  // INDEX_COUNT, always
    body = ExtendedHeaderSize + this->ContentSize + metaHeaderSize + metaSize;
    if (this->Buffer.size() < HeaderSize + body) this->Buffer.resize(HeaderSize + body);  // keeps the content
    uint8_t* b = this->Buffer.data() + HeaderSize;
    Put16(b, static_cast<uint16_t>(ExtendedHeaderSize));
    Put16(b + 2, static_cast<uint16_t>(metaHeaderSize));
    Put32(b + 4, static_cast<uint32_t>(metaSize));
    Put32(b + 8, this->MessageId);
    uint8_t* at = b + ExtendedHeaderSize + this->ContentSize;
    Put16(at, static_cast<uint16_t>(count));
    at += 2;
    for (size_t i = 0; i < count; ++i) {
      Put16(at, static_cast<uint16_t>(std::strlen(metadata[i].Key)));
      Put16(at + 2, 3);  // US-ASCII
      Put32(at + 4, static_cast<uint32_t>(std::strlen(metadata[i].Value)));
      at += 8;
    }
    for (size_t i = 0; i < count; ++i) {
      for (const char* s : {metadata[i].Key, metadata[i].Value}) {
        const size_t n = std::strlen(s);
        std::memcpy(at, s, n);
        at += n;
      }
    }
  }
  this->Pending.BodySize = body;
  this->Pending.Crc = Crc64(this->Buffer.data() + HeaderSize, body);
  WriteHeader(this->Buffer.data(), this->Pending);
  this->Used = HeaderSize + body;
}

std::vector<uint8_t> BuildMessage(uint16_t version, const char* type, const char* deviceName, double timestamp,
                                  const uint8_t* content, size_t contentSize,
                                  const std::vector<std::pair<std::string, std::string>>& metadata, uint32_t messageId) {
  MessageWriter writer;
  uint8_t* out = writer.Begin(version, type, deviceName, timestamp, contentSize, messageId);
  if (contentSize) std::memcpy(out, content, contentSize);
  std::vector<MetaPair> pairs;
  for (const auto& kv : metadata) pairs.push_back({kv.first.c_str(), kv.second.c_str()});
  writer.Finish(pairs.data(), pairs.size());
  return std::vector<uint8_t>(writer.Data(), writer.Data() + writer.Size());
}

std::vector<uint8_t> EncodeTransform(const double m[16]) {
  std::vector<uint8_t> c(TransformSize);
  EncodeTransform(m, c.data());
  return c;
}

}  // namespace igtl
}  // namespace rp
