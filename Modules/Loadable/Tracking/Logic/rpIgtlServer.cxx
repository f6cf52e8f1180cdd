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

#include <igtlQuaternionTrackingDataMessage.h>
#include <igtlStatusMessage.h>
#include <igtlTrackingDataMessage.h>
#include <igtlTransformMessage.h>

#include "rpIgtlProtocol.h"

namespace rp {

namespace {
std::vector<uint8_t> Frame(::igtl::MessageBase* message, uint16_t version, double timestamp,
                           const std::vector<std::pair<std::string, std::string>>& metadata = {}) {
  const double whole = std::floor(timestamp);
  message->SetTimeStamp(static_cast<unsigned int>(whole), static_cast<unsigned int>((timestamp - whole) * 4294967296.0));
  message->Pack();
  const uint8_t* packed = static_cast<const uint8_t*>(message->GetPackPointer());
  if (version < 2) return std::vector<uint8_t>(packed, packed + message->GetPackSize());
  igtl::Header h;
  igtl::ParseHeader(packed, h, UINT64_MAX);
  return igtl::BuildMessage(2, h.Type, h.DeviceName, timestamp, static_cast<const uint8_t*>(message->GetPackBodyPointer()),
                            static_cast<size_t>(message->GetPackBodySize()), metadata);
}

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

bool IgtlServer::Send(Client& c, const std::vector<uint8_t>& message) {
  if (c.Fd < 0) return false;
  size_t done = 0;
  while (done < message.size()) {
    const ssize_t n = ::send(c.Fd, message.data() + done, message.size() - done, MSG_NOSIGNAL);
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
      if (h.Is("STT_TDATA")) {
        auto rts = ::igtl::RTSTrackingDataMessage::New();
        rts->SetDeviceName("Tracker");
        rts->SetStatus(0);
        this->Send(c, Frame(rts, c.Version, now));
      } else {
        auto rts = ::igtl::RTSQuaternionTrackingDataMessage::New();
        rts->SetDeviceName("Tracker");
        rts->SetStatus(0);
        this->Send(c, Frame(rts, c.Version, now));
      }
    } else if (h.Is("STP_TDATA")) {
      c.TData = false;
      auto rts = ::igtl::RTSTrackingDataMessage::New();
      rts->SetDeviceName("Tracker");
      rts->SetStatus(0);
      this->Send(c, Frame(rts, c.Version, now));
    } else if (h.Is("STP_QTDATA")) {
      c.QtData = false;
      auto rts = ::igtl::RTSQuaternionTrackingDataMessage::New();
      rts->SetDeviceName("Tracker");
      rts->SetStatus(0);
      this->Send(c, Frame(rts, c.Version, now));
    } else if (h.Is("GET_STATUS")) {
      auto status = ::igtl::StatusMessage::New();
      status->SetDeviceName("Tracker");
      status->SetCode(::igtl::StatusMessage::STATUS_OK);
      this->Send(c, Frame(status, c.Version, now));
    }
    c.Input.erase(c.Input.begin(), c.Input.begin() + static_cast<long>(igtl::HeaderSize + h.BodySize));
  }
}

void IgtlServer::SendPoses(double now) {
  const int count = this->Source.Count();
  const double wall = WallSeconds();
  std::vector<std::pair<int, ToolPose>> fresh;
  std::vector<std::pair<int, ToolPose>> all;
  for (int i = 0; i < count; ++i) {
    const auto& s = this->Reader.Poll(this->Source, i);
    // TDATA/QTDATA carry no status: only tools with a valid pose go in (as PLUS does).
    if (s.Valid && (s.Pose.State == ToolState::OK || s.Pose.State == ToolState::OutOfVolume)) all.push_back({i, s.Pose});
    if (s.Fresh) fresh.push_back({i, s.Pose});
  }
  for (Client& c : this->Connections) {
    for (const auto& [slot, pose] : fresh) {
      const bool valid = pose.State == ToolState::OK || pose.State == ToolState::OutOfVolume;
      if (!valid && (c.Version < 2 && !this->Opts.SendInvalid)) continue;  // PLUS: a missing tool goes silent
      const std::string fullName = std::string(this->Source.Name(slot)) + this->Opts.Suffix;
      auto message = ::igtl::TransformMessage::New();
      message->SetDeviceName(fullName.substr(0, 20).c_str());
      double m[16];
      pose.ToMatrix(m);
      ::igtl::Matrix4x4 matrix;
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) matrix[r][k] = static_cast<float>(m[4 * r + k]);
      message->SetMatrix(matrix);
      std::vector<std::pair<std::string, std::string>> meta = {{"TransformStatus", TransformStatus(pose.State)}};
      if (fullName.size() > 20) meta.push_back({"IGTL_DEVICE_NAME", fullName});
      this->Send(c, Frame(message, c.Version, wall, meta));
    }
    if ((c.TData || c.QtData) && now >= c.NextTData && !all.empty()) {
      c.NextTData = now + c.TDataInterval;
      if (c.TData) {
        auto message = ::igtl::TrackingDataMessage::New();
        message->SetDeviceName("Tracker");
        for (const auto& [slot, pose] : all) {
          auto e = ::igtl::TrackingDataElement::New();
          e->SetName((std::string(this->Source.Name(slot)) + this->Opts.Suffix).substr(0, 20).c_str());
          e->SetType(::igtl::TrackingDataElement::TYPE_6D);
          double m[16];
          pose.ToMatrix(m);
          ::igtl::Matrix4x4 matrix;
          for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) matrix[r][k] = static_cast<float>(m[4 * r + k]);
          e->SetMatrix(matrix);
          message->AddTrackingDataElement(e);
        }
        this->Send(c, Frame(message, c.Version, wall));
      }
      if (c.QtData) {
        auto message = ::igtl::QuaternionTrackingDataMessage::New();
        message->SetDeviceName("Tracker");
        for (const auto& [slot, pose] : all) {
          auto e = ::igtl::QuaternionTrackingDataElement::New();
          e->SetName((std::string(this->Source.Name(slot)) + this->Opts.Suffix).substr(0, 20).c_str());
          e->SetType(::igtl::QuaternionTrackingDataElement::TYPE_6D);
          e->SetPosition(static_cast<float>(pose.Translation[0]), static_cast<float>(pose.Translation[1]),
                         static_cast<float>(pose.Translation[2]));
          e->SetQuaternion(static_cast<float>(pose.Quaternion[1]), static_cast<float>(pose.Quaternion[2]),
                           static_cast<float>(pose.Quaternion[3]), static_cast<float>(pose.Quaternion[0]));
          message->AddQuaternionTrackingDataElement(e);
        }
        this->Send(c, Frame(message, c.Version, wall));
      }
    }
    if (now - c.LastSend > this->Opts.KeepAliveSeconds) {
      auto status = ::igtl::StatusMessage::New();
      status->SetDeviceName("Tracker");
      status->SetCode(::igtl::StatusMessage::STATUS_OK);
      this->Send(c, Frame(status, c.Version, wall));
    }
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
