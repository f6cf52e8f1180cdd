#pragma once
// OpenIGTLink tracking client: one I/O thread connects (with back-off, never a busy loop),
// reads TRANSFORM / POSITION / TDATA / QTDATA (v1-v3 headers, CRC checked), answers and sends
// keep-alives, and publishes the newest pose per device into a ToolPoseTable. Malformed,
// truncated or oversized input gives a counted, named error; the connection survives when the
// message boundary is intact and is re-made when it is not.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rpIgtlProtocol.h"
#include "rpToolPose.h"

namespace rp {

class IgtlClient {
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
    uint64_t MaxBodySize = 16u << 20;     // larger bodies: oversized, connection dropped
  };

  struct Statistics {
    uint64_t Messages = 0, Poses = 0, CrcErrors = 0, Malformed = 0, Oversized = 0, Skipped = 0;
    uint64_t StatusMessages = 0, RtsMessages = 0, StringMessages = 0, KeepAlivesSent = 0;
    uint64_t Connections = 0, ConnectAttempts = 0;
    int LastRtsStatus = -1;
    int LastStatusCode = -1;
  };

  explicit IgtlClient(Options options);
  ~IgtlClient();
  void Start();
  void Stop();
  bool Connected() const { return this->IsConnected.load(std::memory_order_acquire); }
  Statistics GetStatistics() const;
  std::string LastError() const;
  /// Text of the last STRING message (PLUS command replies and the like).
  std::string LastString() const;
  const ToolPoseTable& Poses() const { return this->Table; }
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
  /// Handles one complete message; false when the stream must be dropped.
  void Dispatch(int fd, const igtl::Header& header, const uint8_t* body);
  void PublishPose(const char* name, size_t nameLength, const ToolPose& pose);
  void Fail(const std::string& message);
  bool Sleep(double seconds);

  Options Opts;
  ToolPoseTable Table;
  std::thread Thread;
  std::atomic<bool> StopRequested{false}, IsConnected{false}, MeasureLatency{false};
  std::atomic<uint64_t> Messages{0}, PosesCount{0}, CrcErrors{0}, Malformed{0}, Oversized{0}, Skipped{0},
      StatusMessages{0}, RtsMessages{0}, StringMessages{0}, KeepAlives{0}, Connections{0}, Attempts{0};
  std::atomic<int> LastRts{-1}, LastStatus{-1};
  std::unique_ptr<std::atomic<uint64_t>[]> Histogram, SocketHistogram;
  double LastKernelReceive = 0;  // I/O thread only: wall time the kernel got the last bytes
  mutable std::mutex TextMutex;  // error text only (error path)
  std::string ErrorText, LastStringText;
  std::vector<uint8_t> Buffer;   // I/O thread only; sized once
  igtl::MessageWriter Writer;    // I/O thread only
};

}  // namespace rp
