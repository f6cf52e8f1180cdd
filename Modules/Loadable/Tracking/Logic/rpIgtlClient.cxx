#include "rpIgtlClient.h"

#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "rpTransformNames.h"

namespace rp {

namespace {
constexpr const char* kOurDeviceName = "RoboPlan";
constexpr size_t kInitialBuffer = 64u << 10;

bool Equals(const char* value, uint32_t size, const char* text) {
  return size == std::strlen(text) && std::memcmp(value, text, size) == 0;
}

// PLUS's TransformStatus (or the older TransformValid) metadata; OK when absent.
ToolState StateFromMetadata(const igtl::Body& body) {
  uint32_t n = 0;
  if (const char* v = body.Find("TransformStatus", n)) {
    if (Equals(v, n, "OK")) return ToolState::OK;
    if (Equals(v, n, "OUT_OF_VOLUME")) return ToolState::OutOfVolume;
    return ToolState::Missing;  // MISSING, OUT_OF_VIEW, INVALID, anything else
  }
  if (const char* v = body.Find("TransformValid", n))
    if (Equals(v, n, "false") || Equals(v, n, "0")) return ToolState::Missing;
  return ToolState::OK;
}

void SwapBytes(uint8_t* data, size_t count, size_t width) {
  for (size_t i = 0; i < count; ++i, data += width) std::reverse(data, data + width);
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
  this->Buffer.resize(kInitialBuffer);
}

IgtlClient::~IgtlClient() { this->Stop(); }

std::unique_ptr<PoseSource> IgtlClient::Create(const PoseSourceConfig& config) {
  Options o;
  std::tie(o.Host, o.Port) = config.HostAndPort();
  const double version = config.Number("header-version", 1);
  if (version != 1 && version != 2) throw std::invalid_argument("header-version must be 1 or 2");
  o.HeaderVersion = static_cast<uint16_t>(version);
  const std::string request = config.Option("request");
  if (!request.empty() && request != "tdata" && request != "qtdata")
    throw std::invalid_argument("request must be tdata or qtdata, got '" + request + "'");
  o.RequestTrackingData = request == "tdata";
  o.RequestQuaternionData = request == "qtdata";
  o.TrackingIntervalMs = static_cast<int>(config.Number("interval-ms", o.TrackingIntervalMs));
  return std::make_unique<IgtlClient>(o);
}

bool IgtlClient::Start(std::string&) {
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void IgtlClient::Stop() { this->Worker.Stop(); }

std::string IgtlClient::StatusText() const {
  if (this->Connected()) return "connected to " + this->Opts.Host + ":" + std::to_string(this->Opts.Port);
  const std::string error = this->Worker.LastError();
  return "connecting" + (error.empty() ? std::string() : ": " + error);
}

nlohmann::json IgtlClient::StatisticsJson() const {
  const auto s = this->GetStatistics();
  return {{"connected", this->Connected()}, {"server", this->Opts.Host + ":" + std::to_string(this->Opts.Port)},
          {"messages", s.Messages}, {"poses", s.Poses}, {"images", s.Images}, {"crcErrors", s.CrcErrors},
          {"malformed", s.Malformed}, {"oversized", s.Oversized}, {"skipped", s.Skipped},
          {"statusMessages", s.StatusMessages}, {"lastStatusCode", s.LastStatusCode}, {"strings", s.StringMessages},
          {"connections", s.Connections}, {"connectAttempts", s.ConnectAttempts}, {"keepAlivesSent", s.KeepAlivesSent},
          {"bytesReceived", s.BytesReceived}, {"lastError", this->LastError()}};
}

IgtlClient::Statistics IgtlClient::GetStatistics() const {
  Statistics s;
  s.Messages = this->Messages;
  s.Poses = this->PosesCount;
  s.Images = this->ImagesCount;
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
  s.BytesReceived = this->Bytes;
  s.LastRtsStatus = this->LastRts;
  s.LastStatusCode = this->LastStatus;
  return s;
}

std::string IgtlClient::LastString() const {
  std::lock_guard<std::mutex> lock(this->StringMutex);
  return this->LastStringText;
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

void IgtlClient::Run() {
  Backoff backoff(this->Opts.ReconnectInitialSeconds, this->Opts.ReconnectMaxSeconds);
  while (!this->Worker.StopRequested()) {
    ++this->Attempts;
    const int fd = this->ConnectOnce();
    if (fd >= 0) {
      ++this->Connections;
      this->IsConnected = true;
      backoff.Reset();
      this->Session(fd);
      this->IsConnected = false;
      this->Ready.Notify();  // the main thread shows the change of state
      ::close(fd);
    }
    this->Worker.Sleep(backoff.Next());  // a dead server costs a few wake-ups per second at most
  }
}

int IgtlClient::ConnectOnce() {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* result = nullptr;
  const std::string port = std::to_string(this->Opts.Port);
  if (getaddrinfo(this->Opts.Host.c_str(), port.c_str(), &hints, &result) != 0 || !result) {
    this->Worker.Fail("cannot resolve host " + this->Opts.Host);
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
    this->Worker.Fail("cannot connect to " + this->Opts.Host + ":" + port + ": " + error);
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

bool IgtlClient::SendControl(int fd, const char* type) {
  this->Writer.Begin(this->Opts.HeaderVersion, type, kOurDeviceName, WallSeconds(), 0);
  this->Writer.Finish();
  return this->SendAll(fd, this->Writer.Data(), this->Writer.Size());
}

void IgtlClient::Session(int fd) {
  const uint16_t version = this->Opts.HeaderVersion;
  for (const char* type : {this->Opts.RequestTrackingData ? "STT_TDATA" : nullptr,
                           this->Opts.RequestQuaternionData ? "STT_QTDATA" : nullptr}) {
    if (!type) continue;
    uint8_t* content = this->Writer.Begin(version, type, kOurDeviceName, WallSeconds(), igtl::StartTrackingSize);
    igtl::EncodeStartTracking(this->Opts.TrackingIntervalMs, TrackerFrameName, content);
    this->Writer.Finish();
    this->SendAll(fd, this->Writer.Data(), this->Writer.Size());
  }
  size_t begin = 0, end = 0;  // unparsed bytes: Buffer[begin, end)
  double lastReceive = SteadySeconds(), lastKeepAlive = lastReceive;
  while (!this->Worker.StopRequested()) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 20);
    const double now = SteadySeconds();
    if (ready > 0) {
      if (end == this->Buffer.size()) {  // compact to make room
        std::memmove(this->Buffer.data(), this->Buffer.data() + begin, end - begin);
        end -= begin;
        begin = 0;
      }
      iovec io{this->Buffer.data() + end, this->Buffer.size() - end};
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
        this->Worker.Fail(end > begin ? "peer closed the connection in the middle of a message (truncated)"
                                      : "peer closed the connection");
        return;
      }
      if (n < 0) {
        if (errno == EAGAIN || errno == EINTR) continue;
        this->Worker.Fail(std::string("receive failed: ") + std::strerror(errno));
        return;
      }
      lastReceive = now;
      end += static_cast<size_t>(n);
      this->Bytes.fetch_add(static_cast<uint64_t>(n), std::memory_order_relaxed);
      const uint64_t published = this->PosesCount.load(std::memory_order_relaxed) + this->ImagesCount.load(std::memory_order_relaxed);
      while (end - begin >= igtl::HeaderSize) {
        igtl::Header header;
        const igtl::Status status = igtl::ParseHeader(this->Buffer.data() + begin, header, this->Opts.MaxBodySize);
        if (status == igtl::Status::BadHeader) {
          ++this->Malformed;
          this->Worker.Fail("malformed OpenIGTLink header (lost message boundary): reconnecting");
          return;
        }
        if (status == igtl::Status::Oversized) {
          ++this->Oversized;
          this->Worker.Fail(std::string("oversized ") + header.Type + " message (" + std::to_string(header.BodySize) +
                            " bytes body, limit " + std::to_string(this->Opts.MaxBodySize) + "): closing the connection");
          return;
        }
        const size_t total = igtl::HeaderSize + static_cast<size_t>(header.BodySize);
        if (end - begin < total) {
          if (total > this->Buffer.size() - begin) {  // make room: move to the front, grow once if needed
            std::memmove(this->Buffer.data(), this->Buffer.data() + begin, end - begin);
            end -= begin;
            begin = 0;
            if (total > this->Buffer.size()) this->Buffer.resize(total);  // bounded by MaxBodySize
          }
          break;
        }
        this->Dispatch(fd, header, this->Buffer.data() + begin + igtl::HeaderSize);
        begin += total;
      }
      if (begin == end) begin = end = 0;
      if (this->PosesCount.load(std::memory_order_relaxed) + this->ImagesCount.load(std::memory_order_relaxed) != published)
        this->Ready.Notify();  // one wake-up per batch received
    } else if (ready < 0 && errno != EINTR) {
      this->Worker.Fail(std::string("poll failed: ") + std::strerror(errno));
      return;
    }
    if (ready > 0 && (p.revents & (POLLERR | POLLHUP)) && !(p.revents & POLLIN)) {
      this->Worker.Fail("connection lost");
      return;
    }
    if (now - lastReceive > this->Opts.DeadSeconds) {
      this->Worker.Fail("no data from the server for " + std::to_string(this->Opts.DeadSeconds) + " s: reconnecting");
      return;
    }
    if (now - lastReceive > this->Opts.KeepAliveSeconds && now - lastKeepAlive > this->Opts.KeepAliveSeconds) {
      if (!this->SendControl(fd, "GET_STATUS")) {
        this->Worker.Fail("send failed: connection lost");
        return;
      }
      ++this->KeepAlives;
      lastKeepAlive = now;
    }
  }
  for (const char* type : {this->Opts.RequestTrackingData ? "STP_TDATA" : nullptr,
                           this->Opts.RequestQuaternionData ? "STP_QTDATA" : nullptr})
    if (type) this->SendControl(fd, type);
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

void IgtlClient::PublishImage(const char* name, size_t nameLength, const igtl::Header& header, const igtl::ImageHeader& h,
                              const uint8_t* pixels) {
  const int slot = this->ImageSlots.FindOrAdd(name, nameLength);
  if (slot < 0) {
    ++this->Skipped;
    return;
  }
  ImageFrame& frame = this->ImageSlots.BeginWrite(slot);
  for (int k = 0; k < 3; ++k) frame.Dimensions[k] = h.Size[k];
  frame.Components = h.Components;
  frame.ScalarType = h.ScalarType;
  h.IjkToRas(frame.IjkToRas);
  frame.Timestamp = header.TimestampSeconds();
  frame.ReceiveTime = SteadySeconds();
  frame.Pixels.resize(frame.ByteCount());  // allocates only when the size changes
  const size_t voxel = static_cast<size_t>(h.Components) * ImageFrame::ScalarBytes(h.ScalarType);
  if (h.IsWholeImage()) {
    std::memcpy(frame.Pixels.data(), pixels, frame.Pixels.size());
  } else {
    // A sub-volume updates the image published last (or a blank one), row by row.
    const ImageFrame* last = this->ImageSlots.LastPublished(slot);
    if (last && last->SameLayout(frame)) std::memcpy(frame.Pixels.data(), last->Pixels.data(), frame.Pixels.size());
    else std::fill(frame.Pixels.begin(), frame.Pixels.end(), uint8_t(0));
    const size_t row = h.SubSize[0] * voxel;
    for (size_t k = 0; k < h.SubSize[2]; ++k)
      for (size_t j = 0; j < h.SubSize[1]; ++j) {
        const size_t at = (((h.SubOffset[2] + k) * h.Size[1] + h.SubOffset[1] + j) * h.Size[0] + h.SubOffset[0]) * voxel;
        std::memcpy(frame.Pixels.data() + at, pixels + (k * h.SubSize[1] + j) * row, row);
      }
  }
  const size_t width = ImageFrame::ScalarBytes(h.ScalarType);
  const bool hostLittle = [] {
    const uint16_t probe = 1;
    uint8_t first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
  }();
  if (width > 1 && (h.Endian == igtl::ImageHeader::LittleEndian) != hostLittle)
    SwapBytes(frame.Pixels.data(), frame.Pixels.size() / width, width);
  this->ImageSlots.EndWrite(slot);
  ++this->ImagesCount;
}

void IgtlClient::Dispatch(int fd, const igtl::Header& header, const uint8_t* data) {
  ++this->Messages;
  auto where = [&] { return std::string(header.Type) + " '" + header.DeviceName + "'"; };  // errors only
  if (this->Opts.CheckCrc && igtl::Crc64(data, header.BodySize) != header.Crc) {
    ++this->CrcErrors;
    this->Worker.Fail("CRC mismatch in " + where() + ": message ignored");
    return;
  }
  igtl::Body body;
  if (igtl::SplitBody(header, data, body) != igtl::Status::Ok) {
    ++this->Malformed;
    this->Worker.Fail("malformed v3 extended header or metadata in " + where());
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
      this->Worker.Fail("malformed TRANSFORM '" + std::string(name, nameLength) + "': body of " +
                        std::to_string(body.ContentSize) + " bytes, expected 48 finite floats");
      return;
    }
    pose.FromMatrix(m);
    pose.State = StateFromMetadata(body);
    this->PublishPose(name, nameLength, pose);
  } else if (header.Is("POSITION")) {
    if (igtl::DecodePosition(body.Content, body.ContentSize, pose.Translation, pose.Quaternion) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Worker.Fail("malformed POSITION '" + std::string(name, nameLength) + "': body of " +
                        std::to_string(body.ContentSize) + " bytes");
      return;
    }
    pose.State = StateFromMetadata(body);
    this->PublishPose(name, nameLength, pose);
  } else if (header.Is("TDATA") || header.Is("QTDATA")) {
    const bool quaternion = header.Is("QTDATA");
    const size_t elementSize = quaternion ? igtl::QtDataElementSize : igtl::TDataElementSize;
    int count = 0;
    if (igtl::CountElements(body.ContentSize, elementSize, count) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Worker.Fail(std::string("malformed ") + header.Type + ": body of " + std::to_string(body.ContentSize) +
                        " bytes is not a whole number of elements");
      return;
    }
    for (int i = 0; i < count; ++i) {
      igtl::TrackingElement e;
      ToolPose p = pose;
      if (quaternion) {
        igtl::DecodeQtDataElement(body.Content + elementSize * static_cast<size_t>(i), e);
        std::copy(e.Position, e.Position + 3, p.Translation);
        const double n = std::sqrt(e.Quaternion[0] * e.Quaternion[0] + e.Quaternion[1] * e.Quaternion[1] +
                                   e.Quaternion[2] * e.Quaternion[2] + e.Quaternion[3] * e.Quaternion[3]);
        if (!(n > 0.5 && n < 1.5) || !std::isfinite(e.Position[0] + e.Position[1] + e.Position[2])) {
          ++this->Malformed;
          continue;
        }
        for (int k = 0; k < 4; ++k) p.Quaternion[k] = e.Quaternion[k] / n;
      } else {
        igtl::DecodeTDataElement(body.Content + elementSize * static_cast<size_t>(i), e);
        bool finite = true;
        for (int k = 0; k < 12; ++k) finite = finite && std::isfinite(e.Matrix[k]);
        if (!finite) {
          ++this->Malformed;
          continue;
        }
        p.FromMatrix(e.Matrix);
      }
      p.State = ToolState::OK;  // TDATA/QTDATA carry only tracked tools
      this->PublishPose(e.Name, std::strlen(e.Name), p);
    }
  } else if (header.Is("IMAGE")) {
    igtl::ImageHeader image;
    const uint8_t* pixels = nullptr;
    if (igtl::DecodeImage(body.Content, body.ContentSize, image, pixels) != igtl::Status::Ok) {
      ++this->Malformed;
      this->Worker.Fail("malformed IMAGE '" + std::string(name, nameLength) + "': header or size of the " +
                        std::to_string(body.ContentSize) + "-byte body do not match");
      return;
    }
    this->PublishImage(name, nameLength, header, image, pixels);
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
      this->Worker.Fail("malformed STRING " + where());
      return;
    }
    ++this->StringMessages;
    std::lock_guard<std::mutex> lock(this->StringMutex);  // rare (command replies), not the pose path
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
