#include "rpIgtlServer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

#include "rpIgtlProtocol.h"

namespace rp {

namespace {
constexpr const char* kCoordinateName = "Tracker";  // device name of TDATA/QTDATA/RTS/STATUS

const char* TransformStatus(ToolState s) {
  switch (s) {
    case ToolState::OK: return "OK";
    case ToolState::OutOfVolume: return "OUT_OF_VOLUME";
    case ToolState::Missing: return "MISSING";
    case ToolState::Disabled: return "INVALID";
  }
  return "INVALID";
}
}  // namespace

IgtlServer::IgtlServer(const ToolPoseTable& source, Options options) : Source(source), Opts(std::move(options)) {}
IgtlServer::~IgtlServer() { this->Stop(); }

bool IgtlServer::Start(std::string& error) {
  this->Stop();
  this->ListenFd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int one = 1;
  setsockopt(this->ListenFd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(this->Opts.Port));
  if (inet_pton(AF_INET, this->Opts.BindAddress.c_str(), &addr.sin_addr) != 1) {
    error = "bad bind address " + this->Opts.BindAddress;
    ::close(this->ListenFd);
    this->ListenFd = -1;
    return false;
  }
  if (::bind(this->ListenFd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(this->ListenFd, 8) != 0) {
    error = "cannot listen on " + this->Opts.BindAddress + ":" + std::to_string(this->Opts.Port) + ": " + std::strerror(errno);
    ::close(this->ListenFd);
    this->ListenFd = -1;
    return false;
  }
  socklen_t len = sizeof addr;
  getsockname(this->ListenFd, reinterpret_cast<sockaddr*>(&addr), &len);
  this->BoundPort = ntohs(addr.sin_port);
  this->StopRequested = false;
  this->Thread = std::thread([this] { this->Run(); });
  return true;
}

void IgtlServer::Stop() {
  if (this->Thread.joinable()) {
    this->StopRequested = true;
    this->Thread.join();
  }
  for (Client& c : this->Connections) ::close(c.Fd);
  this->Connections.clear();
  this->Clients = 0;
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
}

bool IgtlServer::Send(Client& c) {
  if (c.Fd < 0) return false;
  const uint8_t* data = this->Writer.Data();
  const size_t size = this->Writer.Size();
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::send(c.Fd, data + done, size - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{c.Fd, POLLOUT, 0};
      if (::poll(&p, 1, 200) == 1) continue;
    }
    ::close(c.Fd);  // slow or gone: drop this client
    c.Fd = -1;
    return false;
  }
  ++this->Sent;
  c.LastSend = SteadySeconds();
  return true;
}

void IgtlServer::HandleInput(Client& c) {
  while (c.Input.size() >= igtl::HeaderSize) {
    igtl::Header h;
    if (igtl::ParseHeader(c.Input.data(), h, 1u << 20) != igtl::Status::Ok) {
      c.Input.clear();
      ::shutdown(c.Fd, SHUT_RDWR);  // cannot find the next message: drop this client
      return;
    }
    if (c.Input.size() < igtl::HeaderSize + h.BodySize) return;
    if (h.Version >= 2) c.Version = 2;  // the client speaks v2+: answer with v3 framing
    const double now = WallSeconds();
    const uint8_t* body = c.Input.data() + igtl::HeaderSize;
    igtl::Body split;
    igtl::SplitBody(h, body, split);
    if (h.Is("STT_TDATA") || h.Is("STT_QTDATA")) {
      int32_t interval = 0;
      if (split.ContentSize >= 4)
        interval = static_cast<int32_t>((split.Content[0] << 24) | (split.Content[1] << 16) | (split.Content[2] << 8) | split.Content[3]);
      c.TDataInterval = std::max(0.001, interval / 1000.0);
      if (h.Is("STT_TDATA")) c.TData = true;
      else c.QtData = true;
      this->SendRts(c, h.Is("STT_TDATA") ? "RTS_TDATA" : "RTS_QTDATA", now);
    } else if (h.Is("STP_TDATA")) {
      c.TData = false;
      this->SendRts(c, "RTS_TDATA", now);
    } else if (h.Is("STP_QTDATA")) {
      c.QtData = false;
      this->SendRts(c, "RTS_QTDATA", now);
    } else if (h.Is("GET_STATUS")) {
      this->SendStatus(c, now);
    }
    c.Input.erase(c.Input.begin(), c.Input.begin() + static_cast<long>(igtl::HeaderSize + h.BodySize));
  }
}

void IgtlServer::SendRts(Client& c, const char* type, double wall) {
  igtl::EncodeRts(0, this->Writer.Begin(c.Version, type, kCoordinateName, wall, igtl::RtsSize));
  this->Writer.Finish();
  this->Send(c);
}

void IgtlServer::SendStatus(Client& c, double wall) {
  igtl::EncodeStatus(igtl::StatusOk, 0, "", "", this->Writer.Begin(c.Version, "STATUS", kCoordinateName, wall, igtl::StatusSize("")));
  this->Writer.Finish();
  this->Send(c);
}

void IgtlServer::SendPoses(double now) {
  const int count = this->Source.Count();
  const double wall = WallSeconds();
  this->Fresh.clear();
  this->Valid.clear();
  for (int i = 0; i < count; ++i) {
    const auto& s = this->Reader.Poll(this->Source, i);
    // TDATA/QTDATA carry no status: only tools with a valid pose go in (as PLUS does).
    if (s.Valid && (s.Pose.State == ToolState::OK || s.Pose.State == ToolState::OutOfVolume)) this->Valid.push_back(i);
    if (s.Fresh) this->Fresh.push_back(i);
  }
  for (Client& c : this->Connections) {
    for (int slot : this->Fresh) {
      const ToolPose& pose = this->Reader.Last(slot).Pose;
      const bool valid = pose.State == ToolState::OK || pose.State == ToolState::OutOfVolume;
      if (!valid && (c.Version < 2 && !this->Opts.SendInvalid)) continue;  // PLUS: a missing tool goes silent
      const char* name = this->Source.Name(slot);
      double m[16];
      pose.ToMatrix(m);
      igtl::EncodeTransform(m, this->Writer.Begin(c.Version, "TRANSFORM", name, wall, igtl::TransformSize));
      // PLUS's metadata: the status of the transform, and the full name when it is longer than 20.
      const igtl::MetaPair meta[2] = {{"TransformStatus", TransformStatus(pose.State)}, {"IGTL_DEVICE_NAME", name}};
      this->Writer.Finish(meta, std::strlen(name) > igtl::NameSize ? 2 : 1);
      this->Send(c);
    }
    if ((c.TData || c.QtData) && now >= c.NextTData && !this->Valid.empty()) {
      c.NextTData = now + c.TDataInterval;
      if (c.TData) {
        uint8_t* out = this->Writer.Begin(c.Version, "TDATA", kCoordinateName, wall, igtl::TDataElementSize * this->Valid.size());
        for (int slot : this->Valid) {
          double m[16];
          this->Reader.Last(slot).Pose.ToMatrix(m);
          igtl::EncodeTDataElement(this->Source.Name(slot), igtl::TrackingType6D, m, out);
          out += igtl::TDataElementSize;
        }
        this->Writer.Finish();
        this->Send(c);
      }
      if (c.QtData) {
        uint8_t* out = this->Writer.Begin(c.Version, "QTDATA", kCoordinateName, wall, igtl::QtDataElementSize * this->Valid.size());
        for (int slot : this->Valid) {
          const ToolPose& pose = this->Reader.Last(slot).Pose;
          igtl::EncodeQtDataElement(this->Source.Name(slot), igtl::TrackingType6D, pose.Translation, pose.Quaternion, out);
          out += igtl::QtDataElementSize;
        }
        this->Writer.Finish();
        this->Send(c);
      }
    }
    if (now - c.LastSend > this->Opts.KeepAliveSeconds) this->SendStatus(c, wall);
  }
}

void IgtlServer::Run() {
  const double period = 1.0 / std::max(1.0, this->Opts.SendHz);
  double nextSend = SteadySeconds();
  std::vector<pollfd> fds;
  while (!this->StopRequested) {
    fds.clear();
    fds.push_back({this->ListenFd, POLLIN, 0});
    for (const Client& c : this->Connections) fds.push_back({c.Fd, POLLIN, 0});
    const double wait = std::max(0.0, nextSend - SteadySeconds());
    ::poll(fds.data(), fds.size(), static_cast<int>(wait * 1000) + 1);
    if (fds[0].revents & POLLIN) {
      const int fd = ::accept4(this->ListenFd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
      if (fd >= 0) {
        const int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        Client c;
        c.Fd = fd;
        c.LastSend = SteadySeconds();
        this->Connections.push_back(std::move(c));
      }
    }
    for (size_t i = 1; i < fds.size(); ++i) {
      if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      Client& c = this->Connections[i - 1];
      uint8_t buffer[4096];
      const ssize_t n = ::recv(c.Fd, buffer, sizeof buffer, 0);
      if (n <= 0 && !(n < 0 && (errno == EAGAIN || errno == EINTR))) {
        ::close(c.Fd);
        c.Fd = -1;
        continue;
      }
      if (n > 0) {
        c.Input.insert(c.Input.end(), buffer, buffer + n);
        this->HandleInput(c);
      }
    }
    const double now = SteadySeconds();
    if (now >= nextSend) {
      nextSend = std::max(nextSend + period, now);
      this->SendPoses(now);
    }
    // Drop clients that went away or could not keep up.
    for (auto it = this->Connections.begin(); it != this->Connections.end();) {
      if (it->Fd < 0) it = this->Connections.erase(it);
      else ++it;
    }
    this->Clients = static_cast<int>(this->Connections.size());
  }
}

}  // namespace rp
