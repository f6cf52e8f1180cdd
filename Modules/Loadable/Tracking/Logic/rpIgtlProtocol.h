#pragma once
// OpenIGTLink wire format, written and read here (no OpenIGTLink library in the product): the
// 58-byte header (v1/v2), the v3 extended header + metadata framing of header version 2,
// CRC-64/ECMA-182, and the bodies RoboPlan sends and receives: TRANSFORM, POSITION, TDATA,
// QTDATA, STATUS, STRING, IMAGE, STT_/STP_/RTS_ TDATA/QTDATA and GET_STATUS.
// Decoders are plain functions on a byte buffer (callable from fuzz targets); they never
// allocate. Writing goes through MessageWriter, which allocates only when a message is larger
// than any before. Checked byte for byte against upstream OpenIGTLink 3.x (rpIgtlUpstreamTest).
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rp {
namespace igtl {

constexpr size_t HeaderSize = 58;
constexpr size_t ExtendedHeaderSize = 12;  // header version 2: before the content
constexpr size_t TransformSize = 48;
constexpr size_t PositionSize = 28;         // position + quaternion (x y z w)
constexpr size_t TDataElementSize = 70;
constexpr size_t QtDataElementSize = 50;
constexpr size_t StatusHeaderSize = 30;     // + status string + NUL
constexpr size_t StartTrackingSize = 36;    // STT_TDATA / STT_QTDATA
constexpr size_t RtsSize = 1;               // RTS_TDATA / RTS_QTDATA
constexpr size_t StringHeaderSize = 4;
constexpr size_t ImageHeaderSize = 72;
constexpr size_t NameSize = 20;             // device and element names on the wire
constexpr size_t CommandHeaderSize = 138;   // COMMAND / RTS_COMMAND: id, name[128], encoding, length
constexpr size_t CommandNameSize = 128;
constexpr uint8_t TrackingType6D = 2;       // TDATA/QTDATA element type (IGTL_TDATA_TYPE_6D)
constexpr int StatusOk = 1;                 // STATUS code (IGTL_STATUS_OK)

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

/// The content of a body: v1 the whole body; header version 2 the part between the extended
/// header and the metadata. Metadata items beyond Capacity are ignored. A metadata header of
/// size 0 (RoboPlan before the framing fix) is read as "no metadata"; otherwise it starts
/// with the 2-byte INDEX_COUNT, as upstream always writes it.
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

// ---- decoders (content of a body, after SplitBody)

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
/// STRING: encoding (3 = US-ASCII) and the text (not NUL terminated; points into content).
Status DecodeString(const uint8_t* content, size_t size, uint16_t& encoding, const char*& text, size_t& length) noexcept;
/// COMMAND / RTS_COMMAND (v3): the command id, its name (NUL terminated) and the text (points
/// into content, not NUL terminated).
Status DecodeCommand(const uint8_t* content, size_t size, uint32_t& id, char name[CommandNameSize + 1], const char*& text,
                     size_t& length) noexcept;
/// STT_TDATA / STT_QTDATA: the interval asked for (ms) and the coordinate name.
Status DecodeStartTracking(const uint8_t* content, size_t size, int32_t& resolutionMs, char coordinateName[33]) noexcept;
/// RTS_TDATA / RTS_QTDATA: 0 success, 1 error.
Status DecodeRts(const uint8_t* content, size_t size, int& status) noexcept;

/// IMAGE header (72 bytes) and where its pixels are. The pixels are the sub-volume
/// SubSize at SubOffset of the Size image, Components values per voxel, in Endian order.
struct ImageHeader {
  enum Scalar : uint8_t { Int8 = 2, UInt8 = 3, Int16 = 4, UInt16 = 5, Int32 = 6, UInt32 = 7, Float32 = 10, Float64 = 11 };
  enum : uint8_t { BigEndian = 1, LittleEndian = 2, RAS = 1, LPS = 2 };
  uint16_t Version = 1;
  uint8_t Components = 1;
  uint8_t ScalarType = UInt8;
  uint8_t Endian = LittleEndian;
  uint8_t Coordinate = RAS;
  uint16_t Size[3] = {0, 0, 0};
  float Matrix[12] = {};  // columns i, j, k scaled by the spacing, then the image centre
  uint16_t SubOffset[3] = {0, 0, 0};
  uint16_t SubSize[3] = {0, 0, 0};
  /// Bytes of one scalar (0 for an unknown type).
  static size_t ScalarBytes(uint8_t scalarType) noexcept;
  /// Bytes of the pixel data the message carries (the sub-volume).
  uint64_t DataBytes() const noexcept;
  bool IsWholeImage() const noexcept;
  /// IJK of the whole image to RAS, row-major 4x4: spacing and directions from the matrix,
  /// origin = the centre the message gives minus half the extent (OpenIGTLink puts the origin
  /// at the image centre, Slicer/VTK at the first voxel); LPS messages are turned into RAS.
  void IjkToRas(double m[16]) const noexcept;
};
/// Validates the header (types, sizes, a sub-volume inside the image, a non-degenerate
/// matrix) and that the pixel data has exactly the expected size.
Status DecodeImage(const uint8_t* content, size_t size, ImageHeader& header, const uint8_t*& pixels) noexcept;

// ---- encoders (content of a body; sizes above)

void EncodeTransform(const double m[16], uint8_t out[TransformSize]) noexcept;
/// Quaternion in as w x y z (written x y z w).
void EncodePosition(const double position[3], const double quaternion[4], uint8_t out[PositionSize]) noexcept;
void EncodeTDataElement(const char* name, uint8_t type, const double m[16], uint8_t out[TDataElementSize]) noexcept;
void EncodeQtDataElement(const char* name, uint8_t type, const double position[3], const double quaternion[4],
                         uint8_t out[QtDataElementSize]) noexcept;
size_t StatusSize(const char* statusString) noexcept;
void EncodeStatus(int code, int64_t subCode, const char* errorName, const char* statusString, uint8_t* out) noexcept;
void EncodeStartTracking(int32_t resolutionMs, const char* coordinateName, uint8_t out[StartTrackingSize]) noexcept;
void EncodeRts(int status, uint8_t out[RtsSize]) noexcept;
/// STRING content: StringHeaderSize + length bytes, US-ASCII.
void EncodeString(const char* text, size_t length, uint8_t* out) noexcept;
/// COMMAND / RTS_COMMAND content: CommandHeaderSize + length bytes, US-ASCII.
void EncodeCommand(uint32_t id, const char* name, const char* text, size_t length, uint8_t* out) noexcept;
/// IMAGE content: ImageHeaderSize + header.DataBytes(); the pixels are copied after the header.
void EncodeImage(const ImageHeader& header, const uint8_t* pixels, uint8_t* out) noexcept;

struct MetaPair {
  const char* Key;
  const char* Value;
};

/// Frames messages into one reusable buffer: Begin() gives the place for the content, the
/// caller writes it, Finish() adds the metadata (header version 2 only), the header and the
/// CRC. Header version 2 always writes the metadata header's INDEX_COUNT (2 bytes, also
/// when there is no metadata), as upstream OpenIGTLink 3.x writes and reads it.
class MessageWriter {
 public:
  uint8_t* Begin(uint16_t version, const char* type, const char* deviceName, double timestamp, size_t contentSize,
                 uint32_t messageId = 0);
  void Finish(const MetaPair* metadata = nullptr, size_t count = 0);
  const uint8_t* Data() const { return this->Buffer.data(); }
  size_t Size() const { return this->Used; }

 private:
  std::vector<uint8_t> Buffer;
  Header Pending;
  size_t ContentSize = 0, Used = 0;
  uint32_t MessageId = 0;
};

/// Wraps a content into a complete message: version 1 (plain) or 2 (v3 framing with the
/// extended header and metadata). Allocates: tests and tools, not hot paths.
std::vector<uint8_t> BuildMessage(uint16_t version, const char* type, const char* deviceName, double timestamp,
                                  const uint8_t* content, size_t contentSize,
                                  const std::vector<std::pair<std::string, std::string>>& metadata = {},
                                  uint32_t messageId = 0);
/// A TRANSFORM content (48 bytes) from a row-major 4x4.
std::vector<uint8_t> EncodeTransform(const double m[16]);

}  // namespace igtl
}  // namespace rp
