#pragma once
// OpenIGTLink client (pose source "igtl"): one I/O thread connects (with back-off, never a busy
// loop), reads TRANSFORM / POSITION / TDATA / QTDATA (header v1 and v2, CRC checked) into a
// ToolPoseTable and IMAGE into an ImageTable (newest per device name), answers GET_STATUS,
// sends GET_STATUS keep-alives and STT_/STP_ requests. Malformed, truncated or oversized input
// gives a counted, named error; the connection survives when the message boundary is intact
// and is re-made when it is not. Memory is bounded: the receive buffer grows at most to
// MaxBodySize, larger bodies drop the connection.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rpIgtlProtocol.h"
#include "rpImageTable.h"
#include "rpPoseSource.h"
#include "rpToolPose.h"
#include "rpWorkerThread.h"

namespace rp {

class IgtlClient : public PoseSource {
 public:
  struct Options {
    std::string Host = "127.0.0.1";
    int Port = 18944;
    bool CheckCrc = true;
    uint16_t HeaderVersion = 1;           // what we send: 1 (any peer) or 2 (v3 framing: PLUS then adds metadata)
    bool RequestTrackingData = false;     // send STT_TDATA on connect (STP_TDATA on stop)
    bool RequestQuaternionData = false;   // send STT_QTDATA on connect
    int TrackingIntervalMs = 16;
    double KeepAliveSeconds = 1.0;        // quiet this long → send GET_STATUS
    double DeadSeconds = 3.0;             // quiet this long → drop and reconnect
    double ReconnectInitialSeconds = 0.1;
    double ReconnectMaxSeconds = 2.0;
    uint64_t MaxBodySize = 64u << 20;     // larger bodies: oversized, connection dropped
  };

  struct Statistics {
    uint64_t Messages = 0, Poses = 0, Images = 0, CrcErrors = 0, Malformed = 0, Oversized = 0, Skipped = 0;
    uint64_t StatusMessages = 0, RtsMessages = 0, StringMessages = 0, KeepAlivesSent = 0;
    uint64_t Connections = 0, ConnectAttempts = 0, BytesReceived = 0;
    int LastRtsStatus = -1;
    int LastStatusCode = -1;
  };

  explicit IgtlClient(Options options);
  ~IgtlClient() override;
  /// Options from a configuration (Address HOST:PORT; options "header-version" 1|2, "request"
  /// tdata|qtdata, "interval-ms"). Throws std::invalid_argument.
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config);

  // PoseSource
  bool Start(std::string& error) override;
  void Stop() override;
  const ToolPoseTable& Poses() const override { return this->Table; }
  const ImageTable* Images() const override { return &this->ImageSlots; }
  bool Connected() const override { return this->IsConnected.load(std::memory_order_acquire); }
  std::string StatusText() const override;
  nlohmann::json StatisticsJson() const override;

  using PoseSource::Start;
  Statistics GetStatistics() const;
  std::string LastError() const { return this->Worker.LastError(); }
  /// Text of the last STRING message (PLUS command replies and the like).
  std::string LastString() const;
  /// Latency from the sender's header timestamp to the pose being in the buffer (wall clock;
  /// meaningful when both ends share a clock, e.g. loopback): histogram of 1 µs bins, 0-20 ms.
  static constexpr int LatencyBins = 20000;
  std::vector<uint64_t> LatencyHistogram() const;
  /// Socket-to-buffer: from the kernel's receive timestamp of the bytes (SO_TIMESTAMPNS) to
  /// the pose being in the buffer (scheduling of this thread + parsing), same bins.
  std::vector<uint64_t> SocketLatencyHistogram() const;
  static double HistogramPercentile(const std::vector<uint64_t>& histogram, double p);
  void EnableLatency(bool on) { this->MeasureLatency = on; }

 private:
  void Run();
  int ConnectOnce();
  void Session(int fd);
  bool SendAll(int fd, const uint8_t* data, size_t size);
  bool SendControl(int fd, const char* type);  // a message with no content
  /// Handles one complete message (CRC, framing, body).
  void Dispatch(int fd, const igtl::Header& header, const uint8_t* body);
  void PublishPose(const char* name, size_t nameLength, const ToolPose& pose);
  void PublishImage(const char* name, size_t nameLength, const igtl::Header& header, const igtl::ImageHeader& image,
                    const uint8_t* pixels);

  Options Opts;
  ToolPoseTable Table;
  ImageTable ImageSlots;
  WorkerThread Worker;
  std::atomic<bool> IsConnected{false}, MeasureLatency{false};
  std::atomic<uint64_t> Messages{0}, PosesCount{0}, ImagesCount{0}, CrcErrors{0}, Malformed{0}, Oversized{0}, Skipped{0},
      StatusMessages{0}, RtsMessages{0}, StringMessages{0}, KeepAlives{0}, Connections{0}, Attempts{0}, Bytes{0};
  std::atomic<int> LastRts{-1}, LastStatus{-1};
  std::unique_ptr<std::atomic<uint64_t>[]> Histogram, SocketHistogram;
  mutable std::mutex StringMutex;  // STRING text only (rare: command replies)
  std::string LastStringText;
  // I/O thread only
  double LastKernelReceive = 0;  // wall time the kernel got the last bytes
  std::vector<uint8_t> Buffer;   // grows with the largest message (at most MaxBodySize + header)
  igtl::MessageWriter Writer;
};

}  // namespace rp
