#pragma once
// OpenIGTLink wire format for tracking (v1/v2 headers and v3 extended header + metadata):
// CRC-64/ECMA-182, a 58-byte header parser and non-allocating body decoders for TRANSFORM,
// POSITION, TDATA, QTDATA, STATUS and RTS_*. Builds messages with the OpenIGTLink library
// elsewhere; the v3 framing (which Debian's protocol-2 build lacks) is written here.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rp {
namespace igtl {

constexpr size_t HeaderSize = 58;

uint64_t Crc64(const void* data, size_t length, uint64_t crc = 0) noexcept;

enum class Status : uint8_t { Ok = 0, Truncated, BadHeader, Oversized, BadCrc, BadBody, BadMetadata };
const char* StatusName(Status status) noexcept;

struct Header {
  uint16_t Version = 1;
  char Type[13] = {};
  char DeviceName[21] = {};
  uint64_t Timestamp = 0;  // upper 32 bits seconds since 1970, lower 32 fraction
  uint64_t BodySize = 0;
  uint64_t Crc = 0;
  double TimestampSeconds() const { return (Timestamp >> 32) + (Timestamp & 0xFFFFFFFFull) / 4294967296.0; }
  bool Is(const char* type) const;
};

/// Parses the 58-byte header. BadHeader: a version or type that no peer sends (the stream is
/// out of step); Oversized: a body larger than maxBodySize.
Status ParseHeader(const uint8_t* data, Header& header, uint64_t maxBodySize) noexcept;
void WriteHeader(uint8_t* out, const Header& header) noexcept;
uint64_t ToIgtlTimestamp(double secondsSince1970) noexcept;

/// A metadata key/value pair pointing into the message body.
struct MetaItem {
  const char* Key = nullptr;
  uint16_t KeySize = 0;
  const char* Value = nullptr;
  uint32_t ValueSize = 0;
};

/// The content of a body: v1/v2 the whole body, v3 the part between the extended header and
/// the metadata. Metadata items beyond Capacity are ignored.
struct Body {
  static constexpr int Capacity = 16;
  const uint8_t* Content = nullptr;
  size_t ContentSize = 0;
  uint32_t MessageId = 0;
  int MetaCount = 0;
  MetaItem Meta[Capacity];
  /// Value of a metadata key, or nullptr (size in valueSize).
  const char* Find(const char* key, uint32_t& valueSize) const noexcept;
};
Status SplitBody(const Header& header, const uint8_t* body, Body& out) noexcept;

/// TRANSFORM: 48 bytes → row-major 4x4.
Status DecodeTransform(const uint8_t* content, size_t size, double m[16]) noexcept;
/// POSITION: 12 (position), 24 (+ qx qy qz) or 28 (+ w) bytes. Quaternion out as w x y z.
Status DecodePosition(const uint8_t* content, size_t size, double position[3], double quaternion[4]) noexcept;

struct TrackingElement {
  char Name[21] = {};
  uint8_t Type = 0;
  double Matrix[16];     // TDATA (row-major)
  double Position[3];    // QTDATA
  double Quaternion[4];  // QTDATA, w x y z
};
/// Number of elements in a TDATA (70-byte) or QTDATA (50-byte) body; BadBody when the size
/// is not a multiple.
Status CountElements(size_t size, size_t elementSize, int& count) noexcept;
void DecodeTDataElement(const uint8_t* element, TrackingElement& out) noexcept;
void DecodeQtDataElement(const uint8_t* element, TrackingElement& out) noexcept;

/// STATUS: code (1 = OK) and the error name.
Status DecodeStatus(const uint8_t* content, size_t size, int& code, char errorName[21]) noexcept;

/// Wraps a v1/v2 content into a complete message: version 1 (plain) or 2 (v3 framing with the
/// extended header and metadata). Fills in body size and CRC. Allocates: not for hot paths.
std::vector<uint8_t> BuildMessage(uint16_t version, const char* type, const char* deviceName, double timestamp,
                                  const uint8_t* content, size_t contentSize,
                                  const std::vector<std::pair<std::string, std::string>>& metadata = {},
                                  uint32_t messageId = 0);
/// A TRANSFORM content (48 bytes) from a row-major 4x4.
std::vector<uint8_t> EncodeTransform(const double m[16]);

}  // namespace igtl
}  // namespace rp
