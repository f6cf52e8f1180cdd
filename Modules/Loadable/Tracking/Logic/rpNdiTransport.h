#pragma once
// The byte link under the NDI Combined API driver, one interface for every way a tracker is
// reached: a serial port (Polaris, Aurora, older Vega set-ups; PosixSerialTransport) or TCP
// (Polaris Vega and Lyra on Ethernet, port 8765; TcpTransport). The driver's framing, CRC,
// reply parsing, stale tools, reconnect and back-off sit above it and are the same for both.
// What differs is said here: a serial line has a baud rate and a break, a socket has neither
// (the driver then skips COMM and resets with the RESET command).
#include <cstddef>
#include <string>

namespace rp {

class NdiTransport {
 public:
  virtual ~NdiTransport() = default;
  virtual bool Open() = 0;
  virtual void Close() = 0;
  virtual bool IsOpen() const = 0;
  /// Writes all bytes; false on error (the port went away).
  virtual bool Write(const void* data, size_t length) = 0;
  /// Waits up to timeoutMs for bytes: >0 bytes read, 0 timeout, -1 the link went away.
  virtual long Read(void* data, size_t capacity, int timeoutMs) = 0;
  /// False when the link has no baud rate (TCP): the driver then sends no COMM.
  virtual bool HasBaudRate() const { return true; }
  virtual bool SetBaudRate(int baud) = 0;
  /// False when no break can be sent (TCP): the driver then uses the RESET command.
  virtual bool SendBreak(int milliseconds) = 0;
  /// Discards pending input and output.
  virtual void Flush() = 0;
  virtual const std::string& LastError() const = 0;
};

}  // namespace rp
