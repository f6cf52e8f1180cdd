#include "rpIgtlClient.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

namespace rp {

namespace {
constexpr const char* kOurDeviceName = "RoboPlan";

ToolState StateFromMetadata(const igtl::Body& body) {
  uint32_t n = 0;
  const char* v = body.Find("TransformStatus", n);
  if (v) {
    const std::string s(v, n);
    if (s == "OK") return ToolState::OK;
    if (s == "OUT_OF_VOLUME") return ToolState::OutOfVolume;
    return ToolState::Missing;  // MISSING, OUT_OF_VIEW, INVALID, anything else
  }
  v = body.Find("TransformValid", n);
  if (v && (std::string(v, n) == "false" || std::string(v, n) == "0")) return ToolState::Missing;
  return ToolState::OK;
}
}  // namespace

IgtlClient::IgtlClient(Options options)
    : Opts(std::move(options)),
      Histogram(new std::atomic<uint64_t>[LatencyBins]),
      SocketHistogram(new std::atomic<uint64_t>[LatencyBins]) {
  for (int i = 0; i < LatencyBins; ++i) {
    this->Histogram[i].store(0, std::memory_order_relaxed);
    this->SocketHistogram[i].store(0, std::memory_order_relaxed);
  }
  this->Buffer.resize(1u << 20);
}

IgtlClient::~IgtlClient() { this->Stop(); }

void IgtlClient::Start() {
  if (this->Thread.joinable()) return;
  this->StopRequested = false;
  this->Thread = std::thread([this] { this->Run(); });
}

void IgtlClient::Stop() {
  if (!this->Thread.joinable()) return;
  this->StopRequested = true;
  this->Thread.join();
}

IgtlClient::Statistics IgtlClient::GetStatistics() const {
  Statistics s;
  s.Messages = this->Messages;
  s.Poses = this->PosesCount;
  s.CrcErrors = this->CrcErrors;
  s.Malformed = this->Malformed;
  s.Oversized = this->Oversized;
  s.Skipped = this->Skipped;
  s.StatusMessages = this->StatusMessages;
  s.RtsMessages = this->RtsMessages;
  s.StringMessages = this->StringMessages;
  s.KeepAlivesSent = this->KeepAlives;
  s.Connections = this->Connections;
  s.ConnectAttempts = this->Attempts;
  s.LastRtsStatus = this->LastRts;
  s.LastStatusCode = this->LastStatus;
  return s;
}

std::string IgtlClient::LastString() const {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  return this->LastStringText;
}

std::string IgtlClient::LastError() const {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  return this->ErrorText;
}

void IgtlClient::Fail(const std::string& message) {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  this->ErrorText = message;
}

std::vector<uint64_t> IgtlClient::SocketLatencyHistogram() const {
  std::vector<uint64_t> h(LatencyBins);
  for (int i = 0; i < LatencyBins; ++i) h[static_cast<size_t>(i)] = this->SocketHistogram[i].load(std::memory_order_relaxed);
  return h;
}

std::vector<uint64_t> IgtlClient::LatencyHistogram() const {
  std::vector<uint64_t> h(LatencyBins);
  for (int i = 0; i < LatencyBins; ++i) h[static_cast<size_t>(i)] = this->Histogram[i].load(std::memory_order_relaxed);
  return h;
}

double IgtlClient::HistogramPercentile(const std::vector<uint64_t>& histogram, double p) {
  uint64_t total = 0;
  for (uint64_t c : histogram) total += c;
  if (total == 0) return 0;
  const double target = p * static_cast<double>(total);
  uint64_t running = 0;
  for (size_t i = 0; i < histogram.size(); ++i) {
    running += histogram[i];
    if (static_cast<double>(running) >= target) return (static_cast<double>(i) + 1) * 1e-6;
  }
  return static_cast<double>(histogram.size()) * 1e-6;
}

bool IgtlClient::Sleep(double seconds) {
  const double end = SteadySeconds() + seconds;
  while (!this->StopRequested) {
    const double left = end - SteadySeconds();
    if (left <= 0) return true;
    std::this_thread::sleep_for(std::chrono::duration<double>(std::min(left, 0.02)));
  }
  return false;
}

void IgtlClient::Run() {
  double backoff = this->Opts.ReconnectInitialSeconds;
  while (!this->StopRequested) {
    ++this->Attempts;
    const int fd = this->ConnectOnce();
    if (fd >= 0) {
      ++this->Connections;
      this->IsConnected = true;
      backoff = this->Opts.ReconnectInitialSeconds;
      this->Session(fd);
      this->IsConnected = false;
      ::close(fd);
    }
    if (this->StopRequested) break;
    this->Sleep(backoff);  // back off: a dead server costs a few wake-ups per second at most
    backoff = std::min(2 * backoff, this->Opts.ReconnectMaxSeconds);
  }
}

int IgtlClient::ConnectOnce() {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* result = nullptr;
  const std::string port = std::to_string(this->Opts.Port);
  if (getaddrinfo(this->Opts.Host.c_str(), port.c_str(), &hints, &result) != 0 || !result) {
    this->Fail("cannot resolve host " + this->Opts.Host);
    return -1;
  }
  int fd = -1;
  std::string error = "connection refused";
  for (addrinfo* a = result; a && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
    if (fd < 0) continue;
    if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0 && errno != EINPROGRESS) {
      error = std::strerror(errno);
      ::close(fd);
      fd = -1;
      continue;
    }
    pollfd p{fd, POLLOUT, 0};
    int soError = 0;
    socklen_t len = sizeof soError;
    if (::poll(&p, 1, 1000) != 1 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &soError, &len) != 0 || soError != 0) {
      error = soError ? std::strerror(soError) : "connect timed out";
      ::close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(result);
  if (fd < 0) {
    this->Fail("cannot connect to " + this->Opts.Host + ":" + port + ": " + error);
    return -1;
  }
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);  // kernel receive time (latency figures)
  return fd;
}

bool IgtlClient::SendAll(int fd, const uint8_t* data, size_t size) {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::send(fd, data + done, size - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{fd, POLLOUT, 0};
      if (::poll(&p, 1, 500) == 1) continue;
    }
    return false;
  }
  return true;
}

void IgtlClient::Session(int fd) {
  const uint16_t version = this->Opts.HeaderVersion;
  for (const char* type : {this->Opts.RequestTrackingData ? "STT_TDATA" : nullptr,
                           this->Opts.RequestQuaternionData ? "STT_QTDATA" : nullptr}) {
    if (!type) continue;
    uint8_t* content = this->Writer.Begin(version, type, kOurDeviceName, WallSeconds(), igtl::StartTrackingSize);
    igtl::EncodeStartTracking(this->Opts.TrackingIntervalMs, "Tracker", content);
    this->Writer.Finish();
    this->SendAll(fd, this->Writer.Data(), this->Writer.Size());
  }
  uint8_t* buffer = this->Buffer.data();
  const size_t capacity = this->Buffer.size();
  size_t begin = 0, end = 0;
  uint64_t skipRemaining = 0;  // bytes of a too-large-to-buffer body still to discard
  double lastReceive = SteadySeconds(), lastKeepAlive = lastReceive;
  while (!this->StopRequested) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 20);
    const double now = SteadySeconds();
    if (ready > 0) {
      if (begin > 0 && end == begin) begin = end = 0;
      if (end == capacity && begin > 0) {  // compact to make room
        std::memmove(buffer, buffer + begin, end - begin);
        end -= begin;
        begin = 0;
      }
      iovec io{buffer + end, capacity - end};
      alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
      msghdr message{};
      message.msg_iov = &io;
      message.msg_iovlen = 1;
      message.msg_control = control;
      message.msg_controllen = sizeof control;
      const ssize_t n = ::recvmsg(fd, &message, 0);
      for (cmsghdr* c = CMSG_FIRSTHDR(&message); n > 0 && c; c = CMSG_NXTHDR(&message, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
          timespec ts;
          std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
          this->LastKernelReceive = static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
        }
      }
      if (n == 0) {
        this->Fail(end > begin || skipRemaining ? "peer closed the connection in the middle of a message (truncated)"
                                                : "peer closed the connection");
        return;
      }
      if (n < 0) {
        if (errno == EAGAIN || errno == EINTR) continue;
        this->Fail(std::string("receive failed: ") + std::strerror(errno));
        return;
      }
      lastReceive = now;
      end += static_cast<size_t>(n);
      if (skipRemaining) {
        const size_t drop = static_cast<size_t>(std::min<uint64_t>(skipRemaining, end - begin));
        begin += drop;
        skipRemaining -= drop;
      }
      while (!skipRemaining && end - begin >= igtl::HeaderSize) {
        igtl::Header header;
        const igtl::Status status = igtl::ParseHeader(buffer + begin, header, this->Opts.MaxBodySize);
        if (status == igtl::Status::BadHeader) {
          ++this->Malformed;
          this->Fail("malformed OpenIGTLink header (lost message boundary): reconnecting");
          return;
        }
        if (status == igtl::Status::Oversized) {
          ++this->Oversized;
          this->Fail(std::string("oversized ") + header.Type + " message (" + std::to_string(header.BodySize) +
                     " bytes body, limit " + std::to_string(this->Opts.MaxBodySize) + "): closing the connection");
          return;
        }
        const uint64_t total = igtl::HeaderSize + header.BodySize;
        if (total > capacity) {  // allowed but larger than our buffer (e.g. an IMAGE): discard it
          ++this->Messages;
          ++this->Skipped;
          const size_t have = end - begin;
          begin = end;
          skipRemaining = total - have;
          break;
        }
        if (end - begin < total) {
          if (begin + total > capacity) {  // make room for the rest of this message
            std::memmove(buffer, buffer + begin, end - begin);
            end -= begin;
            begin = 0;
          }
          break;
        }
        this->Dispatch(fd, header, buffer + begin + igtl::HeaderSize);
        begin += static_cast<size_t>(total);
      }
    } else if (ready < 0 && errno != EINTR) {
      this->Fail(std::string("poll failed: ") + std::strerror(errno));
      return;
    }
    if (ready > 0 && (p.revents & (POLLERR | POLLHUP)) && !(p.revents & POLLIN)) {
      this->Fail("connection lost");
      return;
    }
    if (now - lastReceive > this->Opts.DeadSeconds) {
      this->Fail("no data from the server for " + std::to_string(this->Opts.DeadSeconds) + " s: reconnecting");
      return;
    }
    if (now - lastReceive > this->Opts.KeepAliveSeconds && now - lastKeepAlive > this->Opts.KeepAliveSeconds) {
      this->Writer.Begin(version, "GET_STATUS", kOurDeviceName, WallSeconds(), 0);
      this->Writer.Finish();
      if (!this->SendAll(fd, this->Writer.Data(), this->Writer.Size())) {
        this->Fail("send failed: connection lost");
        return;
      }
      ++this->KeepAlives;
      lastKeepAlive = now;
    }
  }
  for (const char* type : {this->Opts.RequestTrackingData ? "STP_TDATA" : nullptr,
                           this->Opts.RequestQuaternionData ? "STP_QTDATA" : nullptr}) {
    if (!type) continue;
    this->Writer.Begin(version, type, kOurDeviceName, WallSeconds(), 0);
    this->Writer.Finish();
    this->SendAll(fd, this->Writer.Data(), this->Writer.Size());
  }
}

void IgtlClient::PublishPose(const char* name, size_t nameLength, const ToolPose& pose) {
  const int slot = this->Table.FindOrAdd(name, nameLength);
  if (slot < 0) {
    ++this->Skipped;
    return;
  }
  this->Table.Publish(slot, pose);
  ++this->PosesCount;
  if (this->MeasureLatency.load(std::memory_order_relaxed)) {
    const double now = WallSeconds();
    auto bin = [](double latency) {
      const long b = static_cast<long>(latency * 1e6);
      return b < 0 ? 0L : (b >= LatencyBins ? static_cast<long>(LatencyBins - 1) : b);
    };
    this->Histogram[bin(now - pose.Timestamp)].fetch_add(1, std::memory_order_relaxed);
    if (this->LastKernelReceive > 0)
      this->SocketHistogram[bin(now - this->LastKernelReceive)].fetch_add(1, std::memory_order_relaxed);
  }
}

void IgtlClient::Dispatch(int fd, const igtl::Header& header, const uint8_t* data) {
  ++this->Messages;
  auto where = [&] { return std::string(header.Type) + " '" + header.DeviceName + "'"; };  // errors only
  if (this->Opts.CheckCrc && igtl::Crc64(data, header.BodySize) != header.Crc) {
    ++this->CrcErrors;
    this->Fail("CRC mismatch in " + where() + ": message ignored");
    return;
  }
  igtl::Body body;
  if (igtl::SplitBody(header, data, body) != igtl::Status::Ok) {
    ++this->Malformed;
    this->Fail("malformed v3 extended header or metadata in " + where());
    return;
  }
  // PLUS truncates names over 20 characters and puts the full one in metadata.
  uint32_t nameLength = 0;
  const char* name = body.Find("IGTL_DEVICE_NAME", nameLength);
  if (!name) {
    name = header.DeviceName;
    nameLength = static_cast<uint32_t>(std::strlen(header.DeviceName));
  }
  ToolPose pose;
  pose.Timestamp = header.TimestampSeconds();
  pose.ReceiveTime = SteadySeconds();
  if (header.Is("TRANSFORM")) {
    double m[16];
    if (igtl::DecodeTransform(body.Content, body.ContentSize, m) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Fail("malformed TRANSFORM '" + std::string(name, nameLength) + "': body of " + std::to_string(body.ContentSize) +
                 " bytes, expected 48 finite floats");
      return;
    }
    pose.FromMatrix(m);
    pose.State = StateFromMetadata(body);
    this->PublishPose(name, nameLength, pose);
  } else if (header.Is("POSITION")) {
    if (igtl::DecodePosition(body.Content, body.ContentSize, pose.Translation, pose.Quaternion) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Fail("malformed POSITION '" + std::string(name, nameLength) + "': body of " + std::to_string(body.ContentSize) + " bytes");
      return;
    }
    pose.State = StateFromMetadata(body);
    this->PublishPose(name, nameLength, pose);
  } else if (header.Is("TDATA") || header.Is("QTDATA")) {
    const bool quaternion = header.Is("QTDATA");
    int count = 0;
    if (igtl::CountElements(body.ContentSize, quaternion ? 50 : 70, count) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Fail(std::string("malformed ") + header.Type + ": body of " + std::to_string(body.ContentSize) +
                 " bytes is not a whole number of elements");
      return;
    }
    for (int i = 0; i < count; ++i) {
      igtl::TrackingElement e;
      ToolPose p = pose;
      if (quaternion) {
        igtl::DecodeQtDataElement(body.Content + 50 * i, e);
        std::copy(e.Position, e.Position + 3, p.Translation);
        const double n = std::sqrt(e.Quaternion[0] * e.Quaternion[0] + e.Quaternion[1] * e.Quaternion[1] +
                                   e.Quaternion[2] * e.Quaternion[2] + e.Quaternion[3] * e.Quaternion[3]);
        if (!(n > 0.5 && n < 1.5)) {
          ++this->Malformed;
          continue;
        }
        for (int k = 0; k < 4; ++k) p.Quaternion[k] = e.Quaternion[k] / n;
      } else {
        igtl::DecodeTDataElement(body.Content + 70 * i, e);
        bool finite = true;
        for (int k = 0; k < 12; ++k) finite = finite && std::isfinite(e.Matrix[k]);
        if (!finite) {
          ++this->Malformed;
          continue;
        }
        p.FromMatrix(e.Matrix);
      }
      p.State = ToolState::OK;
      this->PublishPose(e.Name, std::strlen(e.Name), p);
    }
  } else if (header.Is("STATUS")) {
    int code = 0;
    char errorName[21];
    if (igtl::DecodeStatus(body.Content, body.ContentSize, code, errorName) == igtl::Status::Ok) {
      ++this->StatusMessages;
      this->LastStatus = code;
    } else {
      ++this->Malformed;
    }
  } else if (header.Is("RTS_TDATA") || header.Is("RTS_QTDATA")) {
    int status = -1;
    if (igtl::DecodeRts(body.Content, body.ContentSize, status) != igtl::Status::Ok) {
      ++this->Malformed;
      return;
    }
    ++this->RtsMessages;
    this->LastRts = status;
  } else if (header.Is("STRING")) {
    uint16_t encoding = 0;
    const char* text = nullptr;
    size_t length = 0;
    if (igtl::DecodeString(body.Content, body.ContentSize, encoding, text, length) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Fail("malformed STRING " + where());
      return;
    }
    ++this->StringMessages;
    std::lock_guard<std::mutex> lock(this->TextMutex);  // rare (command replies), not the pose path
    this->LastStringText.assign(text, length);
  } else if (header.Is("GET_STATUS")) {
    uint8_t* content = this->Writer.Begin(this->Opts.HeaderVersion, "STATUS", kOurDeviceName, WallSeconds(), igtl::StatusSize(""));
    igtl::EncodeStatus(igtl::StatusOk, 0, "", "", content);
    this->Writer.Finish();
    this->SendAll(fd, this->Writer.Data(), this->Writer.Size());
  } else {
    ++this->Skipped;
  }
}

}  // namespace rp
