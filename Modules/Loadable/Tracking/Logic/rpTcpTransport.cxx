#include "rpTcpTransport.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace rp {

namespace {
std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }
}  // namespace

bool ParseNdiTcpAddress(const std::string& address, std::string& host, int& port, std::string& error) {
  port = NdiTcpDefaultPort;
  std::string portText;
  if (!address.empty() && address.front() == '[') {
    const size_t close = address.find(']');
    if (close == std::string::npos) return error = "bad address '" + address + "' (missing ']')", false;
    host = address.substr(1, close - 1);
    if (close + 1 < address.size()) {
      if (address[close + 1] != ':') return error = "bad address '" + address + "'", false;
      portText = address.substr(close + 2);
    }
  } else {
    const size_t colon = address.rfind(':');
    host = address.substr(0, colon);
    if (colon != std::string::npos) portText = address.substr(colon + 1);
  }
  if (host.empty()) return error = "no host in '" + address + "' (expected HOST or HOST:PORT)", false;
  if (!portText.empty()) {
    char* end = nullptr;
    const long value = std::strtol(portText.c_str(), &end, 10);
    if (*end != '\0' || value < 1 || value > 65535) return error = "bad port '" + portText + "' in '" + address + "'", false;
    port = static_cast<int>(value);
  }
  return true;
}

TcpTransport::TcpTransport(std::string host, int port, int connectTimeoutMs)
    : Host(std::move(host)), Port(port), ConnectTimeoutMs(connectTimeoutMs) {}
TcpTransport::~TcpTransport() { this->Close(); }

bool TcpTransport::Open() {
  this->Close();
  const std::string where = this->Host + ":" + std::to_string(this->Port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(this->Host.c_str(), std::to_string(this->Port).c_str(), &hints, &found);
  if (rc != 0) {
    this->Error = "cannot resolve " + this->Host + ": " + gai_strerror(rc);
    return false;
  }
  this->Error = "cannot connect to " + where;
  for (addrinfo* a = found; a && this->Fd < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
    if (fd < 0) continue;
    if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0 && errno != EINPROGRESS) {
      this->Error = Errno("cannot connect to " + where);
      ::close(fd);
      continue;
    }
    pollfd pfd{fd, POLLOUT, 0};
    int soError = 0;
    socklen_t length = sizeof soError;
    if (::poll(&pfd, 1, this->ConnectTimeoutMs) <= 0) {
      this->Error = "cannot connect to " + where + ": no answer within " + std::to_string(this->ConnectTimeoutMs) + " ms";
      ::close(fd);
      continue;
    }
    if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &soError, &length) != 0 || soError != 0) {
      errno = soError;
      this->Error = Errno("cannot connect to " + where);
      ::close(fd);
      continue;
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    this->Fd = fd;
  }
  ::freeaddrinfo(found);
  if (this->Fd >= 0) this->Error.clear();
  return this->Fd >= 0;
}

void TcpTransport::Close() {
  if (this->Fd >= 0) ::close(this->Fd);
  this->Fd = -1;
}

bool TcpTransport::Write(const void* data, size_t length) {
  const char* p = static_cast<const char*>(data);
  while (length > 0) {
    if (this->Fd < 0) return this->Error = "not connected", false;
    const ssize_t n = ::send(this->Fd, p, length, MSG_NOSIGNAL);
    if (n > 0) {
      p += n;
      length -= static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd pfd{this->Fd, POLLOUT, 0};
      if (::poll(&pfd, 1, 1000) <= 0 || (pfd.revents & (POLLERR | POLLHUP))) return this->Error = "send timed out or connection lost", false;
      continue;
    }
    this->Error = Errno("send failed");
    return false;
  }
  return true;
}

long TcpTransport::Read(void* data, size_t capacity, int timeoutMs) {
  if (this->Fd < 0) return this->Error = "not connected", -1;
  pollfd pfd{this->Fd, POLLIN, 0};
  int ready;
  do ready = ::poll(&pfd, 1, timeoutMs);
  while (ready < 0 && errno == EINTR);
  if (ready < 0) return this->Error = Errno("poll failed"), -1;
  if (ready == 0) return 0;
  const ssize_t n = ::recv(this->Fd, data, capacity, 0);
  if (n > 0) return n;
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return 0;
  this->Error = n == 0 ? std::string("connection closed by the tracker") : Errno("recv failed");
  return -1;
}

bool TcpTransport::SendBreak(int) {
  this->Error = "no serial break over TCP";
  return false;
}

void TcpTransport::Flush() {
  char scratch[4096];
  while (this->Fd >= 0 && ::recv(this->Fd, scratch, sizeof scratch, MSG_DONTWAIT) > 0) {
  }
}

}  // namespace rp
