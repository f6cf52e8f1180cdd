#pragma once
// The serial NdiTransport: a POSIX serial port (termios; termios2/BOTHER for 921600
// and 1228739 baud) or a pseudo-terminal. A pty carries no serial break, so "send break" is a
// hook the owner supplies (the simulator is told out of band: a callback in-process, a unix
// datagram socket `<port>.break` across processes).
#include <functional>
#include <memory>
#include <string>

#include "rpNdiTransport.h"

namespace rp {

class PosixSerialTransport : public NdiTransport {
 public:
  explicit PosixSerialTransport(std::string path);
  ~PosixSerialTransport() override;
  bool Open() override;
  void Close() override;
  bool IsOpen() const override { return this->Fd >= 0; }
  bool Write(const void* data, size_t length) override;
  long Read(void* data, size_t capacity, int timeoutMs) override;
  bool SetBaudRate(int baud) override;
  bool SendBreak(int milliseconds) override;
  void Flush() override;
  const std::string& LastError() const override { return this->Error; }

  /// Replaces the hardware break (tcsendbreak) by an out-of-band notification.
  void SetBreakHook(std::function<bool(int milliseconds)> hook) { this->BreakHook = std::move(hook); }
  const std::string& Path() const { return this->PortPath; }
  int Descriptor() const { return this->Fd; }

 private:
  std::string PortPath, Error;
  int Fd = -1;
  std::function<bool(int)> BreakHook;
};

/// Sets any baud rate, including non-standard ones, with termios2/BOTHER. False on failure.
bool SetCustomBaudRate(int fd, int baud, std::string& error);

/// Opens a new pseudo-terminal: master fd (non-blocking, raw) and the slave's path.
bool OpenPseudoTerminal(int& masterFd, std::string& slavePath, std::string& error);

/// Out-of-band break across processes: a datagram to the unix socket `path`.
bool SendBreakDatagram(const std::string& socketPath, int milliseconds);

/// For a serial path given by the user: a transport with the out-of-band break hook when
/// `<path>.break` exists (a simulator's pty), plain tcsendbreak otherwise.
std::unique_ptr<PosixSerialTransport> MakeSerialTransport(const std::string& path);

}  // namespace rp
