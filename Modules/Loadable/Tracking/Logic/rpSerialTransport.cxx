#include "rpSerialTransport.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace rp {

namespace {
std::string Errno(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

void MakeRaw(int fd) {
  termios t;
  if (tcgetattr(fd, &t) != 0) return;
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  tcsetattr(fd, TCSANOW, &t);
}
}  // namespace

PosixSerialTransport::PosixSerialTransport(std::string path) : PortPath(std::move(path)) {}
PosixSerialTransport::~PosixSerialTransport() { this->Close(); }

bool PosixSerialTransport::Open() {
  this->Close();
  this->Fd = ::open(this->PortPath.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (this->Fd < 0) {
    this->Error = Errno(("cannot open " + this->PortPath).c_str());
    return false;
  }
  if (!isatty(this->Fd)) {
    this->Error = this->PortPath + " is not a serial port";
    this->Close();
    return false;
  }
  MakeRaw(this->Fd);
  this->SetBaudRate(9600);
  this->Flush();
  return true;
}

void PosixSerialTransport::Close() {
  if (this->Fd >= 0) ::close(this->Fd);
  this->Fd = -1;
}

bool PosixSerialTransport::Write(const void* data, size_t length) {
  const char* p = static_cast<const char*>(data);
  while (length > 0) {
    if (this->Fd < 0) {
      this->Error = "port not open";
      return false;
    }
    const ssize_t n = ::write(this->Fd, p, length);
    if (n > 0) {
      p += n;
      length -= static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd pfd{this->Fd, POLLOUT, 0};
      if (::poll(&pfd, 1, 1000) <= 0 || (pfd.revents & (POLLERR | POLLHUP))) {
        this->Error = "write timed out or port hung up";
        return false;
      }
      continue;
    }
    this->Error = Errno("write failed");
    return false;
  }
  return true;
}

long PosixSerialTransport::Read(void* data, size_t capacity, int timeoutMs) {
  if (this->Fd < 0) {
    this->Error = "port not open";
    return -1;
  }
  pollfd pfd{this->Fd, POLLIN, 0};
  int ready;
  do ready = ::poll(&pfd, 1, timeoutMs);
  while (ready < 0 && errno == EINTR);
  if (ready < 0) {
    this->Error = Errno("poll failed");
    return -1;
  }
  if (ready == 0) return 0;
  const ssize_t n = ::read(this->Fd, data, capacity);
  if (n > 0) return n;
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  // EIO (pty master gone) or EOF: the cable was pulled.
  this->Error = n == 0 ? std::string("port closed (EOF)") : Errno("read failed");
  return -1;
}

bool PosixSerialTransport::SetBaudRate(int baud) {
  if (this->Fd < 0) return false;
  speed_t speed = 0;
  switch (baud) {
    case 9600: speed = B9600; break;
    case 14400: speed = 0; break;
    case 19200: speed = B19200; break;
    case 38400: speed = B38400; break;
    case 57600: speed = B57600; break;
    case 115200: speed = B115200; break;
    case 230400: speed = B230400; break;
    case 921600: speed = 0; break;  // BOTHER: some adapters only honour the exact value
    default: speed = 0; break;
  }
  if (speed != 0) {
    termios t;
    if (tcgetattr(this->Fd, &t) != 0 || cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0 ||
        tcsetattr(this->Fd, TCSANOW, &t) != 0) {
      this->Error = Errno("setting baud rate failed");
      return false;
    }
    return true;
  }
  return SetCustomBaudRate(this->Fd, baud, this->Error);
}

bool PosixSerialTransport::SendBreak(int milliseconds) {
  if (this->BreakHook) return this->BreakHook(milliseconds);
  if (this->Fd < 0) return false;
  // tcsendbreak's duration is implementation-defined; TIOCSBRK/TIOCCBRK would give exact timing,
  // the NDI only needs "long enough" (> 250 ms on Linux for a nonzero argument).
  if (tcsendbreak(this->Fd, milliseconds) != 0) {
    this->Error = Errno("tcsendbreak failed");
    return false;
  }
  return true;
}

void PosixSerialTransport::Flush() {
  if (this->Fd >= 0) tcflush(this->Fd, TCIOFLUSH);
}

bool OpenPseudoTerminal(int& masterFd, std::string& slavePath, std::string& error) {
  masterFd = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (masterFd < 0) {
    error = Errno("posix_openpt failed");
    return false;
  }
  char name[128];
  if (grantpt(masterFd) != 0 || unlockpt(masterFd) != 0 || ptsname_r(masterFd, name, sizeof name) != 0) {
    error = Errno("pty set-up failed");
    ::close(masterFd);
    masterFd = -1;
    return false;
  }
  slavePath = name;
  const int flags = fcntl(masterFd, F_GETFL);
  fcntl(masterFd, F_SETFL, flags | O_NONBLOCK);
  MakeRaw(masterFd);
  return true;
}

bool SendBreakDatagram(const std::string& socketPath, int milliseconds) {
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (socketPath.size() >= sizeof addr.sun_path) {
    ::close(fd);
    return false;
  }
  std::strncpy(addr.sun_path, socketPath.c_str(), sizeof addr.sun_path - 1);
  const std::string message = "BREAK " + std::to_string(milliseconds);
  const ssize_t n = ::sendto(fd, message.data(), message.size(), 0, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  ::close(fd);
  if (n < 0) return false;
  usleep(static_cast<useconds_t>(milliseconds) * 1000);  // a break takes time on a wire too
  return true;
}

std::unique_ptr<PosixSerialTransport> MakeSerialTransport(const std::string& path) {
  auto transport = std::make_unique<PosixSerialTransport>(path);
  const std::string breakSocket = path + ".break";
  struct stat st;
  if (::stat(breakSocket.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)) {
    transport->SetBreakHook([breakSocket](int ms) { return SendBreakDatagram(breakSocket, ms); });
  }
  return transport;
}

}  // namespace rp
