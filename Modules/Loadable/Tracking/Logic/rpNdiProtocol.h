#pragma once
// NDI Combined API (Polaris, Aurora) framing: CRC16, commands, and the replies a tracking loop
// parses (ASCII with CRC, TX text and BX binary tracking replies). Plain C++: never allocates,
// never throws; every parser reports what is wrong and where.
#include <cstddef>
#include <cstdint>
#include <string>

namespace rp {
namespace ndi {

/// CRC-16/ARC (reflected 0xA001, init 0): the checksum of every NDI command and reply.
uint16_t Crc16(const void* data, size_t length, uint16_t crc = 0) noexcept;

/// Writes "NAME:args" + CRC + "\r" (or "NAME args\r"/"NAME\r" without CRC when args is null
/// and withCrc is false). Returns the length written, 0 when it does not fit.
size_t FormatCommand(char* out, size_t capacity, const char* name, const char* args, bool withCrc = true) noexcept;

/// Readable text of an NDI error code (ERRORxx).
const char* ErrorCodeText(int code) noexcept;

enum class ParseCode : uint8_t {
  Ok = 0,
  Incomplete,       // more bytes needed (framing only)
  Truncated,        // a complete frame whose content ends too early
  BadCrc,
  BadFormat,
  DeviceError,      // the device answered ERRORxx (Result.DeviceError has the code)
  TooManyHandles,
  Oversized,
};
const char* ParseCodeName(ParseCode code) noexcept;

struct ParseResult {
  ParseCode Code = ParseCode::Ok;
  int DeviceError = 0;     // ERRORxx code when Code == DeviceError
  size_t Offset = 0;       // where in the reply the problem was found
  bool Ok() const { return Code == ParseCode::Ok; }
};

/// Splits a byte stream into reply frames: ASCII up to '\r', or a binary BX frame (C4 A5 + len).
/// Returns Ok with frameLength set, Incomplete, or BadFormat/BadCrc/Oversized for a binary header
/// that cannot be right (the caller should resynchronise: drop a byte and try again).
ParseResult FindFrame(const uint8_t* data, size_t length, size_t& frameLength) noexcept;

/// Checks an ASCII reply "<payload><CRC 4 hex>\r": payload/payloadLength point into `frame`.
/// ERRORxx → DeviceError (after the CRC check).
ParseResult CheckAsciiReply(const uint8_t* frame, size_t length, const char*& payload, size_t& payloadLength) noexcept;

/// Port-status bits (TX/BX): usable only when tool-in-port, initialised and enabled are all set.
enum PortStatusBits : uint32_t {
  PortOccupied = 0x01, PortInitialized = 0x10, PortEnabled = 0x20, PortOutOfVolume = 0x40,
  PortPartiallyInVolume = 0x80,
};

enum class HandleState : uint8_t { Valid = 0, Missing, Disabled, Unoccupied };

struct HandleReport {
  uint8_t Handle = 0;
  HandleState State = HandleState::Missing;
  double Quaternion[4] = {1, 0, 0, 0};  // q0 qx qy qz
  double Translation[3] = {0, 0, 0};    // mm
  double Error = 0;                     // mm
  uint32_t PortStatus = 0;
  uint32_t Frame = 0;
  bool OutOfVolume() const { return (PortStatus & PortOutOfVolume) != 0; }
};

constexpr int MaxHandles = 32;

struct TrackingReply {
  int Count = 0;
  HandleReport Handles[MaxHandles];
  uint16_t SystemStatus = 0;
};

/// Parses a whole TX reply frame (option 0001, ending in CRC + '\r').
ParseResult ParseTx(const uint8_t* frame, size_t length, TrackingReply& reply) noexcept;
/// Parses a whole BX reply frame (option 0801). An ASCII ERRORxx frame gives DeviceError.
ParseResult ParseBx(const uint8_t* frame, size_t length, TrackingReply& reply) noexcept;

/// Parses "PHSR" payloads: count then per handle 2-hex handle + 3-hex status.
ParseResult ParsePhsr(const char* payload, size_t length, uint8_t* handles, int capacity, int& count) noexcept;

/// Where a port handle's tool is plugged, from a "PHINF:hh0021" reply: 33 characters of basic
/// tool information, then the 14-character port location (8 device number, 1 system, 1 wired '0'
/// or wireless '1', 2 port number "01"-"12" for a wired port, 2 channel in hex). `WiredPort` is
/// numbered as PLUS's PortName: channel * 100 + port - 1 (the channel is a 5-DOF splitter's).
struct PortLocation {
  bool Wired = false;
  int WiredPort = -1;  // -1 for a wireless (passive or active wireless) tool
};
ParseResult ParsePhinfPortLocation(const char* payload, size_t length, PortLocation& location) noexcept;
/// A wired port as PLUS's PortName writes it: an integer 0-9999 (channel * 100 + port - 1).
bool ParseWiredPort(const std::string& text, int& wiredPort);
/// "wired port 2", "wired port 2 channel 1": the port as the device's labels number it.
std::string DescribeWiredPort(int wiredPort);

/// Hex helpers (uppercase or lowercase accepted when reading).
bool ParseHex(const char* text, int digits, uint32_t& value) noexcept;
void WriteHex(char* out, uint32_t value, int digits) noexcept;

}  // namespace ndi
}  // namespace rp
