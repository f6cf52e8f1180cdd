#include "rpNdiProtocol.h"

#include <cstdlib>

#include <cstring>

namespace rp {
namespace ndi {

namespace {

struct CrcTable {
  uint16_t Values[256];
  constexpr CrcTable() : Values() {
    for (int i = 0; i < 256; ++i) {
      uint16_t c = static_cast<uint16_t>(i);
      for (int k = 0; k < 8; ++k) c = (c & 1) ? static_cast<uint16_t>((c >> 1) ^ 0xA001) : static_cast<uint16_t>(c >> 1);
      Values[i] = c;
    }
  }
};
constexpr CrcTable kCrcTable;

ParseResult Fail(ParseCode code, size_t offset, int deviceError = 0) {
  ParseResult r;
  r.Code = code;
  r.Offset = offset;
  r.DeviceError = deviceError;
  return r;
}

bool ParseSignedDecimal(const char* text, int digits, double scale, double& value) {
  if (text[0] != '+' && text[0] != '-') return false;
  long v = 0;
  for (int i = 1; i <= digits; ++i) {
    const char c = text[i];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  value = (text[0] == '-' ? -v : v) * scale;
  return true;
}

uint16_t ReadU16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t ReadU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
float ReadF32(const uint8_t* p) {
  const uint32_t bits = ReadU32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

constexpr size_t kMaxAsciiFrame = 8192;
constexpr size_t kMaxBinaryBody = 8192;

}  // namespace

uint16_t Crc16(const void* data, size_t length, uint16_t crc) noexcept {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < length; ++i) crc = static_cast<uint16_t>((crc >> 8) ^ kCrcTable.Values[(crc ^ p[i]) & 0xFF]);
  return crc;
}

bool ParseHex(const char* text, int digits, uint32_t& value) noexcept {
  uint32_t v = 0;
  for (int i = 0; i < digits; ++i) {
    const char c = text[i];
    uint32_t d;
    if (c >= '0' && c <= '9') d = static_cast<uint32_t>(c - '0');
    else if (c >= 'A' && c <= 'F') d = static_cast<uint32_t>(c - 'A' + 10);
    else if (c >= 'a' && c <= 'f') d = static_cast<uint32_t>(c - 'a' + 10);
    else return false;
    v = (v << 4) | d;
  }
  value = v;
  return true;
}

void WriteHex(char* out, uint32_t value, int digits) noexcept {
  static const char kDigits[] = "0123456789ABCDEF";
  for (int i = digits - 1; i >= 0; --i) {
    out[i] = kDigits[value & 0xF];
    value >>= 4;
  }
}

size_t FormatCommand(char* out, size_t capacity, const char* name, const char* args, bool withCrc) noexcept {
  const size_t nameLength = std::strlen(name);
  const size_t argsLength = args ? std::strlen(args) : 0;
  if (withCrc) {
    const size_t total = nameLength + 1 + argsLength + 4 + 1;
    if (total > capacity) return 0;
    std::memcpy(out, name, nameLength);
    out[nameLength] = ':';
    if (argsLength) std::memcpy(out + nameLength + 1, args, argsLength);
    const size_t body = nameLength + 1 + argsLength;
    WriteHex(out + body, Crc16(out, body), 4);
    out[body + 4] = '\r';
    return total;
  }
  const size_t total = nameLength + (argsLength ? 1 + argsLength : 0) + 1;
  if (total > capacity) return 0;
  std::memcpy(out, name, nameLength);
  size_t n = nameLength;
  if (argsLength) {
    out[n++] = ' ';
    std::memcpy(out + n, args, argsLength);
    n += argsLength;
  }
  out[n++] = '\r';
  return n;
}

const char* ErrorCodeText(int code) noexcept {
  switch (code) {
    case 0x01: return "invalid command";
    case 0x02: return "command too long";
    case 0x03: return "command too short";
    case 0x04: return "invalid CRC calculated for command";
    case 0x05: return "time-out on command execution";
    case 0x06: return "unable to set up new communication parameters";
    case 0x07: return "incorrect number of command parameters";
    case 0x08: return "invalid port handle selected";
    case 0x09: return "invalid mode or priority";
    case 0x0A: return "invalid LED selected";
    case 0x0B: return "invalid LED state selected";
    case 0x0C: return "command invalid in current operating mode";
    case 0x0D: return "no tool plugged in selected port handle";
    case 0x0E: return "selected port handle not initialized";
    case 0x0F: return "selected port handle not enabled";
    case 0x10: return "system not initialized";
    case 0x11: return "unable to stop tracking";
    case 0x12: return "unable to start tracking";
    case 0x13: return "unable to initialize tool";
    case 0x23: return "parameter out of range";
    case 0x2B: return "port handle not allocated";
    case 0x2C: return "port handle has become unoccupied";
    case 0x2D: return "all port handles used";
    case 0x40: return "tool definition file error";
    case 0x41: return "tool characteristics not supported";
    case 0xF1: return "too much infrared light";
    default: return "unknown device error";
  }
}

const char* ParseCodeName(ParseCode code) noexcept {
  switch (code) {
    case ParseCode::Ok: return "ok";
    case ParseCode::Incomplete: return "incomplete reply";
    case ParseCode::Truncated: return "truncated reply";
    case ParseCode::BadCrc: return "CRC mismatch";
    case ParseCode::BadFormat: return "malformed reply";
    case ParseCode::DeviceError: return "device error";
    case ParseCode::TooManyHandles: return "too many handles in reply";
    case ParseCode::Oversized: return "reply too long";
  }
  return "unknown";
}

ParseResult FindFrame(const uint8_t* data, size_t length, size_t& frameLength) noexcept {
  frameLength = 0;
  if (length == 0) return Fail(ParseCode::Incomplete, 0);
  if (data[0] == 0xC4) {
    if (length < 2) return Fail(ParseCode::Incomplete, length);
    if (data[1] == 0xA5) {
      if (length < 6) return Fail(ParseCode::Incomplete, length);
      if (Crc16(data, 4) != ReadU16(data + 4)) return Fail(ParseCode::BadCrc, 4);
      const size_t body = ReadU16(data + 2);
      if (body > kMaxBinaryBody) return Fail(ParseCode::Oversized, 2);
      if (length < body + 8) return Fail(ParseCode::Incomplete, length);
      frameLength = body + 8;
      return ParseResult{};
    }
  }
  const void* cr = std::memchr(data, '\r', length < kMaxAsciiFrame ? length : kMaxAsciiFrame);
  if (!cr) return Fail(length >= kMaxAsciiFrame ? ParseCode::Oversized : ParseCode::Incomplete, length);
  frameLength = static_cast<size_t>(static_cast<const uint8_t*>(cr) - data) + 1;
  return ParseResult{};
}

ParseResult CheckAsciiReply(const uint8_t* frame, size_t length, const char*& payload, size_t& payloadLength) noexcept {
  payload = reinterpret_cast<const char*>(frame);
  payloadLength = 0;
  if (length < 5 || frame[length - 1] != '\r') return Fail(ParseCode::Truncated, length);
  const size_t body = length - 5;
  uint32_t crc;
  if (!ParseHex(payload + body, 4, crc)) return Fail(ParseCode::BadFormat, body);
  if (Crc16(frame, body) != crc) return Fail(ParseCode::BadCrc, body);
  payloadLength = body;
  if (body == 7 && std::memcmp(payload, "ERROR", 5) == 0) {
    uint32_t code = 0;
    if (!ParseHex(payload + 5, 2, code)) return Fail(ParseCode::BadFormat, 5);
    return Fail(ParseCode::DeviceError, 0, static_cast<int>(code));
  }
  return ParseResult{};
}

ParseResult ParseTx(const uint8_t* frame, size_t length, TrackingReply& reply) noexcept {
  reply.Count = 0;
  const char* p;
  size_t n;
  ParseResult r = CheckAsciiReply(frame, length, p, n);
  if (!r.Ok()) return r;
  size_t i = 0;
  auto need = [&](size_t k) { return i + k <= n; };
  uint32_t count;
  if (!need(2)) return Fail(ParseCode::Truncated, i);
  if (!ParseHex(p, 2, count)) return Fail(ParseCode::BadFormat, 0);
  if (count > static_cast<uint32_t>(MaxHandles)) return Fail(ParseCode::TooManyHandles, 0);
  i = 2;
  for (uint32_t h = 0; h < count; ++h) {
    HandleReport& out = reply.Handles[h];
    out = HandleReport{};
    uint32_t handle;
    if (!need(2)) return Fail(ParseCode::Truncated, i);
    if (!ParseHex(p + i, 2, handle)) return Fail(ParseCode::BadFormat, i);
    out.Handle = static_cast<uint8_t>(handle);
    i += 2;
    if (need(7) && std::memcmp(p + i, "MISSING", 7) == 0) {
      out.State = HandleState::Missing;
      i += 7;
      if (!need(16)) return Fail(ParseCode::Truncated, i);
      if (!ParseHex(p + i, 8, out.PortStatus) || !ParseHex(p + i + 8, 8, out.Frame)) return Fail(ParseCode::BadFormat, i);
      i += 16;
    } else if (need(8) && std::memcmp(p + i, "DISABLED", 8) == 0) {
      out.State = HandleState::Disabled;
      i += 8;
    } else if (need(10) && std::memcmp(p + i, "UNOCCUPIED", 10) == 0) {
      out.State = HandleState::Unoccupied;
      i += 10;
    } else {
      out.State = HandleState::Valid;
      // 4 x 6 (quaternion) + 3 x 7 (position) + 6 (error) + 8 + 8 characters.
      if (!need(24 + 21 + 6 + 16)) return Fail(ParseCode::Truncated, i);
      for (int k = 0; k < 4; ++k, i += 6)
        if (!ParseSignedDecimal(p + i, 5, 1e-4, out.Quaternion[k])) return Fail(ParseCode::BadFormat, i);
      for (int k = 0; k < 3; ++k, i += 7)
        if (!ParseSignedDecimal(p + i, 6, 1e-2, out.Translation[k])) return Fail(ParseCode::BadFormat, i);
      if (!ParseSignedDecimal(p + i, 5, 1e-4, out.Error)) return Fail(ParseCode::BadFormat, i);
      i += 6;
      if (!ParseHex(p + i, 8, out.PortStatus) || !ParseHex(p + i + 8, 8, out.Frame)) return Fail(ParseCode::BadFormat, i);
      i += 16;
    }
    if (!need(1)) return Fail(ParseCode::Truncated, i);
    if (p[i] != '\n') return Fail(ParseCode::BadFormat, i);
    ++i;
    reply.Count = static_cast<int>(h + 1);
  }
  uint32_t system;
  if (!need(4)) return Fail(ParseCode::Truncated, i);
  if (!ParseHex(p + i, 4, system)) return Fail(ParseCode::BadFormat, i);
  i += 4;
  if (i != n) return Fail(ParseCode::BadFormat, i);
  reply.SystemStatus = static_cast<uint16_t>(system);
  return ParseResult{};
}

ParseResult ParseBx(const uint8_t* frame, size_t length, TrackingReply& reply) noexcept {
  reply.Count = 0;
  if (length >= 1 && frame[0] != 0xC4) {
    const char* p;
    size_t n;
    ParseResult r = CheckAsciiReply(frame, length, p, n);
    return r.Ok() ? Fail(ParseCode::BadFormat, 0) : r;
  }
  if (length < 8) return Fail(ParseCode::Truncated, length);
  if (frame[1] != 0xA5) return Fail(ParseCode::BadFormat, 1);
  if (Crc16(frame, 4) != ReadU16(frame + 4)) return Fail(ParseCode::BadCrc, 4);
  const size_t bodyLength = ReadU16(frame + 2);
  if (bodyLength + 8 != length) return Fail(bodyLength + 8 > length ? ParseCode::Truncated : ParseCode::BadFormat, 2);
  const uint8_t* body = frame + 6;
  if (Crc16(body, bodyLength) != ReadU16(body + bodyLength)) return Fail(ParseCode::BadCrc, 6 + bodyLength);
  size_t i = 0;
  auto need = [&](size_t k) { return i + k <= bodyLength; };
  if (!need(1)) return Fail(ParseCode::Truncated, 6);
  const int count = body[i++];
  if (count > MaxHandles) return Fail(ParseCode::TooManyHandles, 6);
  for (int h = 0; h < count; ++h) {
    HandleReport& out = reply.Handles[h];
    out = HandleReport{};
    if (!need(2)) return Fail(ParseCode::Truncated, 6 + i);
    out.Handle = body[i];
    const uint8_t status = body[i + 1];
    i += 2;
    if (status == 0x01) {
      out.State = HandleState::Valid;
      if (!need(32)) return Fail(ParseCode::Truncated, 6 + i);
      for (int k = 0; k < 4; ++k, i += 4) out.Quaternion[k] = ReadF32(body + i);
      for (int k = 0; k < 3; ++k, i += 4) out.Translation[k] = ReadF32(body + i);
      out.Error = ReadF32(body + i);
      i += 4;
    } else if (status == 0x02) {
      out.State = HandleState::Missing;
    } else if (status == 0x04) {
      out.State = HandleState::Disabled;
    } else {
      return Fail(ParseCode::BadFormat, 6 + i - 1);
    }
    if (out.State != HandleState::Disabled) {
      if (!need(8)) return Fail(ParseCode::Truncated, 6 + i);
      out.PortStatus = ReadU32(body + i);
      out.Frame = ReadU32(body + i + 4);
      i += 8;
    }
    reply.Count = h + 1;
  }
  if (!need(2)) return Fail(ParseCode::Truncated, 6 + i);
  reply.SystemStatus = ReadU16(body + i);
  i += 2;
  if (i != bodyLength) return Fail(ParseCode::BadFormat, 6 + i);
  return ParseResult{};
}

ParseResult ParsePhsr(const char* payload, size_t length, uint8_t* handles, int capacity, int& count) noexcept {
  count = 0;
  uint32_t n;
  if (length < 2) return Fail(ParseCode::Truncated, length);
  if (!ParseHex(payload, 2, n)) return Fail(ParseCode::BadFormat, 0);
  if (static_cast<int>(n) > capacity) return Fail(ParseCode::TooManyHandles, 0);
  if (length != 2 + 5 * n) return Fail(length < 2 + 5 * n ? ParseCode::Truncated : ParseCode::BadFormat, length);
  for (uint32_t k = 0; k < n; ++k) {
    uint32_t handle, status;
    if (!ParseHex(payload + 2 + 5 * k, 2, handle) || !ParseHex(payload + 4 + 5 * k, 3, status))
      return Fail(ParseCode::BadFormat, 2 + 5 * k);
    handles[k] = static_cast<uint8_t>(handle);
  }
  count = static_cast<int>(n);
  return ParseResult{};
}

ParseResult ParsePhinfPortLocation(const char* payload, size_t length, PortLocation& location) noexcept {
  constexpr size_t kBasic = 33, kLocation = 14;
  location = PortLocation{};
  if (length != kBasic + kLocation) return Fail(length < kBasic + kLocation ? ParseCode::Truncated : ParseCode::BadFormat, length);
  const char* at = payload + kBasic;
  if (at[9] != '0' && at[9] != '1') return Fail(ParseCode::BadFormat, kBasic + 9);
  location.Wired = at[9] == '0';
  if (!location.Wired) return ParseResult{};
  uint32_t channel;
  if (at[10] < '0' || at[10] > '9' || at[11] < '0' || at[11] > '9') return Fail(ParseCode::BadFormat, kBasic + 10);
  if (!ParseHex(at + 12, 2, channel)) return Fail(ParseCode::BadFormat, kBasic + 12);
  const int port = (at[10] - '0') * 10 + (at[11] - '0');
  if (port < 1) return Fail(ParseCode::BadFormat, kBasic + 10);
  location.WiredPort = static_cast<int>(channel) * 100 + port - 1;
  return ParseResult{};
}

bool ParseWiredPort(const std::string& text, int& wiredPort) {
  char* end = nullptr;
  const long port = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || port < 0 || port > 9999) return false;
  wiredPort = static_cast<int>(port);
  return true;
}

std::string DescribeWiredPort(int wiredPort) {
  return "wired port " + std::to_string(wiredPort % 100 + 1) +
         (wiredPort >= 100 ? " channel " + std::to_string(wiredPort / 100) : std::string());
}

}  // namespace ndi
}  // namespace rp
