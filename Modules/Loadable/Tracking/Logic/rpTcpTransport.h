#pragma once
// The TCP NdiTransport: the NDI Combined API over Ethernet, as the Polaris Vega and Lyra serve
// it (port 8765). Same bytes as on a serial line (commands with CRC, ASCII and BX binary
// replies); no baud rate and no break. Connect is bounded by a timeout, TCP_NODELAY is set
// (one small poll per frame), SIGPIPE is never raised (a tracker that drops the connection
// reads as "the link went away", and the driver reconnects with back-off).
#include <string>

#include "rpNdiTransport.h"

namespace rp {

/// Default port of the NDI Combined API on a Vega/Lyra.
constexpr int NdiTcpDefaultPort = 8765;

class TcpTransport : public NdiTransport {
 public:
  TcpTransport(std::string host, int port, int connectTimeoutMs = 3000);
  ~TcpTransport() override;
  bool Open() override;
  void Close() override;
  bool IsOpen() const override { return this->Fd >= 0; }
  bool Write(const void* data, size_t length) override;
  long Read(void* data, size_t capacity, int timeoutMs) override;
  bool HasBaudRate() const override { return false; }
  bool SetBaudRate(int) override { return true; }  // nothing to set on a socket
  bool SendBreak(int) override;
  void Flush() override;
  const std::string& LastError() const override { return this->Error; }

 private:
  std::string Host, Error;
  int Port, ConnectTimeoutMs, Fd = -1;
};

/// "host", "host:port" (default port 8765) or "[v6]:port" → host and port. False with `error`.
bool ParseNdiTcpAddress(const std::string& address, std::string& host, int& port, std::string& error);

}  // namespace rp
