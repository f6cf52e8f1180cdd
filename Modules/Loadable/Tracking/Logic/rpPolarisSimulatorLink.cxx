#include "rpPolarisSimulatorLink.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "rpSerialTransport.h"

namespace rp {

bool PolarisSimulatorLink::Open(std::string& error) {
  if (this->Tcp() ? !this->OpenListener(error) : !this->OpenPty(error)) return false;
  if (!this->Tcp() && !this->Opts.LinkPath.empty() && !this->OpenBreakSocket(error)) {
    this->ClosePty();
    return false;
  }
  this->IsUnplugged = false;
  return true;
}

void PolarisSimulatorLink::Close() {
  this->ClosePty();
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
  if (this->BreakSocketFd >= 0) {
    ::close(this->BreakSocketFd);
    this->BreakSocketFd = -1;
    ::unlink((this->Opts.LinkPath + ".break").c_str());
  }
  if (!this->Tcp() && !this->Opts.LinkPath.empty()) ::unlink(this->Opts.LinkPath.c_str());
}

bool PolarisSimulatorLink::OpenPty(std::string& error) {
  int master;
  std::string slave;
  if (!OpenPseudoTerminal(master, slave, error)) return false;
  // Keep one slave descriptor open ourselves: a master without any slave reads EIO at once.
  const int keep = ::open(slave.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
  if (keep < 0) {
    error = "cannot open pty slave " + slave;
    ::close(master);
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->MasterFd = master;
    this->KeepSlaveFd = keep;
    this->Slave = slave;
  }
  if (!this->Opts.LinkPath.empty()) {
    // Re-point the link atomically so a host re-opening the path finds the new pty.
    const std::string tmp = this->Opts.LinkPath + ".tmp";
    ::unlink(tmp.c_str());
    if (::symlink(slave.c_str(), tmp.c_str()) != 0 || ::rename(tmp.c_str(), this->Opts.LinkPath.c_str()) != 0) {
      error = "cannot create link " + this->Opts.LinkPath + " -> " + slave;
      return false;
    }
  }
  return true;
}

void PolarisSimulatorLink::ClosePty() {
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->MasterFd >= 0) ::close(this->MasterFd);
  if (this->KeepSlaveFd >= 0) ::close(this->KeepSlaveFd);
  this->MasterFd = this->KeepSlaveFd = -1;
}

bool PolarisSimulatorLink::OpenBreakSocket(std::string& error) {
  const std::string socketPath = this->Opts.LinkPath + ".break";
  ::unlink(socketPath.c_str());
  this->BreakSocketFd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, socketPath.c_str(), sizeof addr.sun_path - 1);
  if (this->BreakSocketFd < 0 || socketPath.size() >= sizeof addr.sun_path ||
      ::bind(this->BreakSocketFd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    error = "cannot bind break socket " + socketPath;
    return false;
  }
  return true;
}

bool PolarisSimulatorLink::OpenListener(std::string& error) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int one = 1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // loopback only
  // After an Unplug the same port again, so that a driver retrying its address finds it.
  const int port = this->BoundPort > 0 ? this->BoundPort.load() : this->Opts.TcpPort;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  socklen_t length = sizeof addr;
  if (fd < 0 || ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
      ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 4) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
    error = "cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    return false;
  }
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->ListenFd = fd;
  this->BoundPort = ntohs(addr.sin_port);
  return true;
}

void PolarisSimulatorLink::AcceptClient() {
  const int fd = ::accept4(this->ListenFd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return;
  // One host at a time, as the Vega's API port: a new connection replaces the old one (a host
  // reconnecting after a network fault must not find the device taken by its own dead socket).
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->MasterFd >= 0) ::close(this->MasterFd);
  this->MasterFd = fd;
}

std::string PolarisSimulatorLink::SlavePath() const {
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Slave;
}

std::string PolarisSimulatorLink::PortPath() const {
  if (this->Tcp()) return "127.0.0.1:" + std::to_string(this->BoundPort.load());
  return this->Opts.LinkPath.empty() ? this->SlavePath() : this->Opts.LinkPath;
}

void PolarisSimulatorLink::Unplug() {
  this->IsUnplugged = true;
  // The port disappears, as /dev/ttyUSB0 does when a USB-serial cable is pulled. A link left
  // pointing at the closed pty would name whatever pty the system hands out next under that
  // number (another process's, another simulator's): a host retrying the path would talk to it.
  if (!this->Tcp() && !this->Opts.LinkPath.empty()) ::unlink(this->Opts.LinkPath.c_str());
  // The thread stops touching the fds within one poll period; close them under the lock.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  this->ClosePty();
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
}

bool PolarisSimulatorLink::Replug(std::string& error) {
  if (this->Tcp() ? !this->OpenListener(error) : !this->OpenPty(error)) return false;
  this->BreakPending = false;
  this->IsUnplugged = false;  // the thread resets the device state when it sees the new pty
  return true;
}

void PolarisSimulatorLink::Poll(int timeoutMs, const std::function<void()>& newHost,
                                const std::function<void(const char*, size_t)>& received) {
  int master, listener;
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    master = this->MasterFd;
    listener = this->ListenFd;
  }
  if (master < 0 && listener < 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(timeoutMs));
    return;
  }
  pollfd fds[3] = {{master, POLLIN, 0}, {this->BreakSocketFd, POLLIN, 0}, {listener, POLLIN, 0}};
  const int ready = ::poll(fds, 3, timeoutMs);  // negative descriptors are ignored
  if (ready <= 0 || this->IsUnplugged) return;
  if (fds[2].revents & POLLIN) {
    this->AcceptClient();
    newHost();
  }
  if (this->BreakSocketFd >= 0 && (fds[1].revents & POLLIN)) {
    char message[64];
    while (::recv(this->BreakSocketFd, message, sizeof message, 0) > 0) this->BreakPending = true;
  }
  if (!(fds[0].revents & (POLLIN | POLLHUP | POLLERR))) return;
  char buffer[4096];
  const ssize_t n = ::read(master, buffer, sizeof buffer);
  if (n > 0) {
    received(buffer, static_cast<size_t>(n));
  } else if (this->Tcp() && (n == 0 || (errno != EAGAIN && errno != EINTR))) {
    std::lock_guard<std::mutex> lock(this->Mutex);  // the host hung up: wait for the next one
    if (this->MasterFd == master) {
      ::close(master);
      this->MasterFd = -1;
    }
    newHost();
  }
}

void PolarisSimulatorLink::Send(uint8_t* data, size_t length, bool ascii) {
  if (this->Drops > 0) {
    --this->Drops;
    return;
  }
  if (this->CrcFaults > 0) {
    --this->CrcFaults;
    // Corrupt the checksum itself: the payload stays plausible, only the CRC can tell.
    if (ascii) data[length - 2] = data[length - 2] == '0' ? '1' : '0';
    else data[length - 1] ^= 0x5A;
  }
  const int delay = this->DelayMs;
  if (delay > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay));
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->MasterFd < 0 || this->IsUnplugged) return;
  size_t done = 0;
  while (done < length) {
    const ssize_t n = this->Tcp() ? ::send(this->MasterFd, data + done, length - done, MSG_NOSIGNAL)
                                  : ::write(this->MasterFd, data + done, length - done);
    if (n <= 0) return;  // host not reading: a real device drops it too
    done += static_cast<size_t>(n);
  }
}

}  // namespace rp
