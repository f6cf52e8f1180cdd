#include "rpIgtlServer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "rpPlusConfiguration.h"
#include "rpPlusSequenceFile.h"
#include "rpTransformNames.h"
#include "rpTransformRepository.h"

namespace rp {

IgtlServer::IgtlServer(const ToolPoseTable& source, Options options) : Source(source), Opts(std::move(options)) {}
IgtlServer::~IgtlServer() { this->Stop(); }

bool IgtlServer::StartRecording(const std::string& requested, std::string& message) {
  return this->Recorder.Start(this->Recordings, requested, message);
}

bool IgtlServer::StopRecording(std::string& message) { return this->Recorder.Stop(message); }

bool IgtlServer::GetTransform(const std::string& name, double m[16], ToolState& state, std::string& error) {
  const auto fixed = this->FixedTransforms.find(name);
  if (fixed != this->FixedTransforms.end()) {
    std::copy(fixed->second.begin(), fixed->second.end(), m);
    state = ToolState::OK;
    return true;
  }
  for (int slot = 0; slot < this->Source.Count(); ++slot)
    if (name == this->Source.Name(slot)) {
      ToolPose pose;
      if (this->Source.Read(slot, pose) == 0) break;
      pose.ToMatrix(m);
      state = pose.State;
      return true;
    }
  std::string from, to, split;
  if (this->Opts.Transforms && SplitTransformName(name, from, to, split) && this->Opts.Transforms(from, to, m, state)) return true;
  error = "no transform " + name;
  return false;
}

bool IgtlServer::UpdateTransform(const std::string& name, const double m[16], std::string& error) {
  std::string from, to;
  if (!SplitTransformName(name, from, to, error)) {
    error = "'" + name + "' is not a transform name (FromToTo): " + error;
    return false;
  }
  if (this->Opts.UpdateTransforms) return this->Opts.UpdateTransforms(from, to, m, error);
  this->FixedTransforms[name].assign(m, m + 16);
  return true;
}

void IgtlServer::HandleCommand(Client& c, const igtl::Header& h, const igtl::Body& body, double wall) {
  if (h.Is("COMMAND")) {
    uint32_t id = 0;
    char name[igtl::CommandNameSize + 1];
    const char* text = nullptr;
    size_t length = 0;
    if (igtl::DecodeCommand(body.Content, body.ContentSize, id, name, text, length) != igtl::Status::Ok) return;
    IgtlCommandRequest request;
    const IgtlCommandReply reply = RunIgtlCommand(std::string(text, length), *this, c.Caller, &request);
    this->Note(CommandLogLine(c.Caller, request, reply));
    const std::string xml = CommandReplyXml(reply);
    igtl::EncodeCommand(id, name, xml.data(), xml.size(),
                        this->Writer.Begin(std::max<uint16_t>(c.Version, 2), "RTS_COMMAND", h.DeviceName, wall,
                                           igtl::CommandHeaderSize + xml.size(), id));
    const igtl::MetaPair meta[2] = {{"Status", CommandStatusName(reply)}, {"Message", reply.Message.c_str()}};
    this->Writer.Finish(meta, 2);
    this->Send(c);
    return;
  }
  // STRING "CMD_<uid>" → STRING "ACK_<uid>"
  uint16_t encoding = 0;
  const char* text = nullptr;
  size_t length = 0;
  if (igtl::DecodeString(body.Content, body.ContentSize, encoding, text, length) != igtl::Status::Ok) return;
  IgtlCommandRequest request;
  const IgtlCommandReply reply = RunIgtlCommand(std::string(text, length), *this, c.Caller, &request);
  this->Note(CommandLogLine(c.Caller, request, reply));
  const std::string xml = CommandReplyXml(reply);
  const std::string device = "ACK_" + std::string(h.DeviceName + 4);
  const size_t size = std::min<size_t>(xml.size(), 65535);
  igtl::EncodeString(xml.data(), size, this->Writer.Begin(c.Version, "STRING", device.c_str(), wall, igtl::StringHeaderSize + size));
  this->Writer.Finish();
  this->Send(c);
}

void IgtlServer::HandleClientInfo(Client& c, const igtl::Body& body) {
  uint16_t encoding = 0;
  const char* text = nullptr;
  size_t length = 0;
  if (igtl::DecodeString(body.Content, body.ContentSize, encoding, text, length) != igtl::Status::Ok) return;
  plus::Server info;
  std::string error;
  if (!plus::ParseClientInfo(std::string(text, length), info, error)) return;  // PLUS keeps the old info too
  c.HasClientInfo = true;
  c.WantsTransforms = std::find(info.MessageTypes.begin(), info.MessageTypes.end(), "TRANSFORM") != info.MessageTypes.end();
  c.WantsStrings = std::find(info.MessageTypes.begin(), info.MessageTypes.end(), "STRING") != info.MessageTypes.end();
  c.Wanted.assign(static_cast<size_t>(this->Source.Count()), 0);
  c.Extras.clear();
  for (const plus::TransformName& t : info.TransformNames) {
    bool served = false;
    for (int slot = 0; slot < this->Source.Count(); ++slot)
      if (t.Name == this->Source.Name(slot)) {
        c.Wanted[static_cast<size_t>(slot)] = 1;
        served = true;
      }
    std::string from = t.From, to = t.To, split;
    if (!served && ((!from.empty() && !to.empty()) || SplitTransformName(t.Name, from, to, split)))
      c.Extras.push_back({t.Name, from, to});
  }
}

void IgtlServer::SendTransform(Client& c, const char* name, const double m[16], ToolState state, double wall) {
  igtl::EncodeTransform(m, this->Writer.Begin(c.Version, "TRANSFORM", name, wall, igtl::TransformSize));
  // PLUS's metadata: the status of the transform, and the full name when it is longer than 20.
  const igtl::MetaPair meta[2] = {{"TransformStatus", PlusToolStatusName(state)}, {"IGTL_DEVICE_NAME", name}};
  this->Writer.Finish(meta, std::strlen(name) > igtl::NameSize ? 2 : 1);
  this->Send(c);
}

void IgtlServer::SendExtras(Client& c, double wall) {
  if (!c.WantsTransforms || !this->Opts.Transforms) return;
  for (const Client::Extra& e : c.Extras) {
    double m[16];
    ToolState state = ToolState::Missing;
    if (!this->Opts.Transforms(e.From, e.To, m, state)) continue;  // not connected: nothing to send
    const bool valid = state == ToolState::OK || state == ToolState::OutOfVolume;
    if (!valid && c.Version < 2 && !this->Opts.SendInvalid) continue;
    this->SendTransform(c, e.Name.c_str(), m, state, wall);
  }
}

void IgtlServer::SendOutbox(double wall) {
  const IgtlOutbox* outbox = this->Opts.Outbox;
  outbox->DrainReady();
  IgtlOutbox::Message& m = this->OutboxMessage;
  for (int slot = 0; slot < outbox->Count(); ++slot) {
    const uint64_t published = outbox->Read(slot, m);
    if (published == 0 || published == this->OutboxSent[static_cast<size_t>(slot)]) continue;
    this->OutboxSent[static_cast<size_t>(slot)] = published;
    const bool transform = std::strcmp(m.Type, "TRANSFORM") == 0;
    for (Client& c : this->Connections) {
      if (c.Fd < 0 || (transform && !c.WantsTransforms) || (!transform && !c.WantsStrings)) continue;
      std::memcpy(this->Writer.Begin(c.Version, m.Type, m.Name, wall, m.ContentSize), m.Content, m.ContentSize);
      igtl::MetaPair meta[2];
      size_t count = 0;
      if (transform) meta[count++] = {"TransformStatus", "OK"};  // as the served tools' (PLUS's)
      if (std::strlen(m.Name) > igtl::NameSize) meta[count++] = {"IGTL_DEVICE_NAME", m.Name};
      this->Writer.Finish(meta, count);
      this->Send(c);
    }
  }
}

void IgtlServer::Note(const std::string& line) const {
  if (this->Opts.Log) this->Opts.Log(line);
}

bool IgtlServer::Start(std::string& error) {
  this->Stop();
  this->ListenFd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int one = 1;
  setsockopt(this->ListenFd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(this->Opts.Port));
  Ipv4 bind = 0;
  if (!ParseBindAddress(this->Opts.BindAddress, bind, error) || !this->Recordings.Open(this->Opts.RecordFolder, error)) {
    ::close(this->ListenFd);
    this->ListenFd = -1;
    return false;
  }
  addr.sin_addr.s_addr = htonl(bind);
  if (::bind(this->ListenFd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(this->ListenFd, 64) != 0) {
    error = "cannot listen on " + this->Opts.BindAddress + ":" + std::to_string(this->Opts.Port) + ": " + std::strerror(errno);
    ::close(this->ListenFd);
    this->ListenFd = -1;
    return false;
  }
  socklen_t len = sizeof addr;
  getsockname(this->ListenFd, reinterpret_cast<sockaddr*>(&addr), &len);
  this->BoundPort = ntohs(addr.sin_port);
  this->Note("serving OpenIGTLink on " + FormatIpv4(bind) + ":" + std::to_string(this->BoundPort.load()) +
             (bind == 0 ? " (every interface)" : "") + "; commands that change state or write files from " +
             this->Opts.CommandClients.ToString() + "; recordings in " + this->Recordings.Path());
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void IgtlServer::Stop() {
  this->Worker.Stop();
  if (this->Recorder.Active()) {  // a recording nobody stopped is closed, readable, not lost
    std::string message;
    this->Recorder.Stop(message);
    this->Note("server stopped while recording: " + message);
  }
  for (Client& c : this->Connections)
    if (c.Fd >= 0) ::close(c.Fd);
  this->Connections.clear();
  this->Clients = 0;
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
}

IgtlServer::Statistics IgtlServer::GetStatistics() const {
  Statistics s;
  s.MessagesSent = this->Sent;
  s.MessagesDropped = this->Dropped;
  s.Accepted = this->Accepted;
  s.Refused = this->Refused;
  s.DroppedMalformed = this->Malformed;
  s.DroppedStalled = this->Stalled;
  s.Closed = this->Closed;
  s.BytesSkipped = this->Skipped;
  s.BytesReceived = this->Received;
  return s;
}

void IgtlServer::Drop(Client& c, std::atomic<uint64_t>& reason, const char* why) {
  if (c.Fd < 0) return;
  ::close(c.Fd);
  c.Fd = -1;
  ++reason;
  this->Note("client " + c.Caller.Address + " " + why);
}

bool IgtlServer::Send(Client& c) {
  if (c.Fd < 0) return false;
  const uint8_t* data = this->Writer.Data();
  const size_t size = this->Writer.Size();
  size_t done = 0;
  if (c.Queued.size() == c.QueuedSent) {  // nothing waiting: straight to the socket
    const ssize_t n = ::send(c.Fd, data, size, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno != EAGAIN && errno != EINTR) {
      this->Drop(c, this->Closed, "gone (send failed)");
      return false;
    }
    done = n > 0 ? static_cast<size_t>(n) : 0;
    if (done == size) {
      ++this->Sent;
      c.LastSend = SteadySeconds();
      return true;
    }
    c.Queued.clear();
    c.QueuedSent = 0;
  }
  // The client is behind: queue the rest of the message, up to the bound.
  if (c.Queued.size() - c.QueuedSent + size - done > this->Opts.MaxQueuedOutput) {
    ++this->Dropped;
    return false;
  }
  c.Queued.insert(c.Queued.end(), data + done, data + size);
  if (c.StalledSince == 0) c.StalledSince = SteadySeconds();
  ++this->Sent;
  c.LastSend = SteadySeconds();
  return true;
}

void IgtlServer::Flush(Client& c, double now) {
  if (c.Fd < 0 || c.Queued.size() == c.QueuedSent) return;
  const ssize_t n = ::send(c.Fd, c.Queued.data() + c.QueuedSent, c.Queued.size() - c.QueuedSent, MSG_NOSIGNAL | MSG_DONTWAIT);
  if (n < 0 && errno != EAGAIN && errno != EINTR) {
    this->Drop(c, this->Closed, "gone (send failed)");
    return;
  }
  if (n > 0) {
    c.QueuedSent += static_cast<size_t>(n);
    c.StalledSince = now;  // progress
  }
  if (c.QueuedSent == c.Queued.size()) {
    c.Queued.clear();
    c.QueuedSent = 0;
    c.StalledSince = 0;
  } else if (now - c.StalledSince > this->Opts.StallSeconds) {
    this->Drop(c, this->Stalled, "dropped: it read nothing for too long");  // it would hold output forever
  }
}

void IgtlServer::SendRts(Client& c, const char* type, double wall) {
  igtl::EncodeRts(0, this->Writer.Begin(c.Version, type, TrackerFrameName, wall, igtl::RtsSize));
  this->Writer.Finish();
  this->Send(c);
}

void IgtlServer::SendStatus(Client& c, double wall) {
  igtl::EncodeStatus(igtl::StatusOk, 0, "", "", this->Writer.Begin(c.Version, "STATUS", TrackerFrameName, wall, igtl::StatusSize("")));
  this->Writer.Finish();
  this->Send(c);
}

void IgtlServer::Receive(Client& c, uint8_t* scratch, size_t scratchSize) {
  // Into the parse window, or, while skipping a body we do not keep, into scratch.
  uint8_t* into = c.Skip ? scratch : c.Input.data() + c.InputUsed;
  const size_t room = c.Skip ? std::min<uint64_t>(scratchSize, c.Skip) : c.Input.size() - c.InputUsed;
  const ssize_t n = ::recv(c.Fd, into, room, MSG_DONTWAIT);
  if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
    this->Drop(c, this->Closed, "disconnected");
    return;
  }
  if (n < 0) return;
  this->Received += static_cast<uint64_t>(n);
  if (c.Skip) {
    c.Skip -= static_cast<uint64_t>(n);
    this->Skipped += static_cast<uint64_t>(n);
    return;
  }
  c.InputUsed += static_cast<size_t>(n);
  this->HandleInput(c);
}

void IgtlServer::HandleInput(Client& c) {
  size_t at = 0;
  while (c.Fd >= 0 && c.InputUsed - at >= igtl::HeaderSize) {
    igtl::Header h;
    const igtl::Status status = igtl::ParseHeader(c.Input.data() + at, h, UINT64_MAX);
    if (status != igtl::Status::Ok) {
      this->Drop(c, this->Malformed, "dropped: its stream lost the message boundary");
      return;
    }
    const uint64_t total = igtl::HeaderSize + h.BodySize;
    if (total > c.Input.size()) {
      // A body larger than any control message (an IMAGE, a flood): let it stream past.
      const uint64_t have = c.InputUsed - at;
      c.Skip = total - have;
      this->Skipped += have;
      at = c.InputUsed;
      break;
    }
    if (c.InputUsed - at < total) break;  // the rest is still coming
    const uint8_t* body = c.Input.data() + at + igtl::HeaderSize;
    at += static_cast<size_t>(total);
    if (igtl::Crc64(body, h.BodySize) != h.Crc) continue;  // damaged: ignore it, the stream is in step
    if (h.Version >= 2) c.Version = 2;                      // the client speaks v2+: answer with v3 framing
    igtl::Body split;
    if (igtl::SplitBody(h, body, split) != igtl::Status::Ok) continue;
    const double wall = WallSeconds();
    if (h.Is("STT_TDATA") || h.Is("STT_QTDATA")) {
      int32_t interval = 0;
      char coordinate[33];
      igtl::DecodeStartTracking(split.Content, split.ContentSize, interval, coordinate);
      c.TDataInterval = std::max(0.001, interval / 1000.0);
      (h.Is("STT_TDATA") ? c.TData : c.QtData) = true;
      this->SendRts(c, h.Is("STT_TDATA") ? "RTS_TDATA" : "RTS_QTDATA", wall);
    } else if (h.Is("STP_TDATA")) {
      c.TData = false;
      this->SendRts(c, "RTS_TDATA", wall);
    } else if (h.Is("STP_QTDATA")) {
      c.QtData = false;
      this->SendRts(c, "RTS_QTDATA", wall);
    } else if (h.Is("GET_STATUS")) {
      this->SendStatus(c, wall);
    } else if (h.Is("CLIENTINFO")) {
      this->HandleClientInfo(c, split);
    } else if (h.Is("COMMAND") || (h.Is("STRING") && std::strncmp(h.DeviceName, "CMD_", 4) == 0)) {
      this->HandleCommand(c, h, split, wall);
    }
  }
  if (c.Fd < 0) return;
  std::memmove(c.Input.data(), c.Input.data() + at, c.InputUsed - at);
  c.InputUsed -= at;
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
  if (this->Recorder.Active() && !this->Fresh.empty()) {
    bool stoppedNow = false;
    this->Recorder.Record(wall, this->Source, this->Reader, &stoppedNow);
    if (stoppedNow) this->Note("recording stopped: " + this->Recorder.Problem());
  }
  for (Client& c : this->Connections) {
    if (c.Fd < 0) continue;
    if (c.Queued.size() != c.QueuedSent) {  // behind: it gets the newest poses once it catches up
      this->Dropped += this->Fresh.size();
      continue;
    }
    for (int slot : this->Fresh) {
      if (c.HasClientInfo && (!c.WantsTransforms || static_cast<size_t>(slot) >= c.Wanted.size() || !c.Wanted[static_cast<size_t>(slot)]))
        continue;  // this client's CLIENTINFO does not name it
      const ToolPose& pose = this->Reader.Last(slot).Pose;
      const bool valid = pose.State == ToolState::OK || pose.State == ToolState::OutOfVolume;
      if (!valid && (c.Version < 2 && !this->Opts.SendInvalid)) continue;  // PLUS: a missing tool goes silent
      double m[16];
      pose.ToMatrix(m);
      this->SendTransform(c, this->Source.Name(slot), m, pose.State, wall);
    }
    if (!c.Extras.empty() && !this->Fresh.empty()) this->SendExtras(c, wall);
    if ((c.TData || c.QtData) && now >= c.NextTData && !this->Valid.empty()) {
      c.NextTData = now + c.TDataInterval;
      if (c.TData) {
        uint8_t* out = this->Writer.Begin(c.Version, "TDATA", TrackerFrameName, wall, igtl::TDataElementSize * this->Valid.size());
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
        uint8_t* out = this->Writer.Begin(c.Version, "QTDATA", TrackerFrameName, wall, igtl::QtDataElementSize * this->Valid.size());
        for (int slot : this->Valid) {
          const ToolPose& pose = this->Reader.Last(slot).Pose;
          igtl::EncodeQtDataElement(this->Source.Name(slot), igtl::TrackingType6D, pose.Translation, pose.Quaternion, out);
          out += igtl::QtDataElementSize;
        }
        this->Writer.Finish();
        this->Send(c);
      }
    }
    if (c.Fd >= 0 && now - c.LastSend > this->Opts.KeepAliveSeconds) this->SendStatus(c, wall);
  }
}

void IgtlServer::Accept() {
  for (;;) {
    sockaddr_in peer{};
    socklen_t length = sizeof peer;
    const int fd = ::accept4(this->ListenFd, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd < 0) return;
    const Ipv4 address = ntohl(peer.sin_addr.s_addr);
    const std::string name = FormatIpv4(address) + ":" + std::to_string(ntohs(peer.sin_port));
    if (static_cast<int>(this->Connections.size()) >= this->Opts.MaxClients) {
      ::close(fd);  // full: the clients we serve keep their share
      ++this->Refused;
      this->Note("client " + name + " refused: " + std::to_string(this->Opts.MaxClients) + " clients are connected already");
      continue;
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    if (this->Opts.SocketSendBuffer > 0)
      setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &this->Opts.SocketSendBuffer, sizeof this->Opts.SocketSendBuffer);
    Client c;
    c.Fd = fd;
    c.Caller = {name, this->Opts.CommandClients.Contains(address), this->Opts.CommandClients.ToString()};
    c.LastSend = SteadySeconds();
    c.Input.resize(this->Opts.InputWindow);
    this->Note("client " + name + " connected" +
               (c.Caller.MayChangeState ? " (may change state)" : " (stream and read-only commands)"));
    this->Connections.push_back(std::move(c));
    ++this->Accepted;
  }
}

void IgtlServer::Run() {
  const double period = 1.0 / std::max(1.0, this->Opts.SendHz);
  double nextSend = SteadySeconds();
  std::vector<pollfd> fds;
  std::vector<uint8_t> scratch(64u << 10);  // skipped bodies stream through it
  while (!this->Worker.StopRequested()) {
    fds.clear();
    fds.push_back({this->ListenFd, POLLIN, 0});
    for (const Client& c : this->Connections)
      fds.push_back({c.Fd, static_cast<short>(POLLIN | (c.Queued.size() != c.QueuedSent ? POLLOUT : 0)), 0});
    const size_t polled = this->Connections.size();  // Accept() may add more below
    const IgtlOutbox* outbox = this->Opts.Outbox;
    if (outbox) fds.push_back({outbox->ReadyFd(), POLLIN, 0});  // last: the clients keep indices 1..n
    const double wait = std::max(0.0, nextSend - SteadySeconds());
    ::poll(fds.data(), fds.size(), static_cast<int>(wait * 1000) + 1);
    const double now = SteadySeconds();
    if (fds[0].revents & POLLIN) this->Accept();
    for (size_t i = 1; i <= polled; ++i) {
      Client& c = this->Connections[i - 1];
      if (fds[i].revents & POLLOUT) this->Flush(c, now);
      if (c.Fd >= 0 && (fds[i].revents & (POLLIN | POLLHUP | POLLERR))) this->Receive(c, scratch.data(), scratch.size());
      if (c.Fd >= 0 && c.Queued.size() != c.QueuedSent && now - c.StalledSince > this->Opts.StallSeconds)
        this->Drop(c, this->Stalled, "dropped: it read nothing for too long");
    }
    if (outbox && (fds.back().revents & POLLIN)) this->SendOutbox(WallSeconds());
    if (now >= nextSend) {
      nextSend = std::max(nextSend + period, now);
      if (outbox) this->SendOutbox(WallSeconds());  // also without an eventfd (none left): at the send rate
      this->SendPoses(now);
    }
    // Forget clients that went away or were dropped.
    this->Connections.erase(std::remove_if(this->Connections.begin(), this->Connections.end(),
                                           [](const Client& c) { return c.Fd < 0; }),
                            this->Connections.end());
    this->Clients = static_cast<int>(this->Connections.size());
  }
}

}  // namespace rp
