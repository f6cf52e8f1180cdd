#pragma once
// The NDI Combined API driver (pose sources "serial" and "tcp"): one I/O thread that resets, probes
// and configures the tracker, loads passive tool definitions (and finds wired tools by their port,
// as PLUS's PortName names them), tracks (BX or TX polling at the
// frame rate) and publishes each tool's newest pose into a ToolPoseTable (slot <Tool>ToTracker).
// Unplug is detected and the whole set-up repeated with back-off, without restarting the program.
// The link is an NdiTransport: a serial port, or TCP to a Polaris Vega/Lyra (no COMM, no break).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rpNdiProtocol.h"
#include "rpPoseSource.h"
#include "rpNdiTransport.h"
#include "rpToolPose.h"
#include "rpWorkerThread.h"

namespace rp {

class NdiTracker : public PoseSource {
 public:
  struct Tool {
    std::string Name;            // tool name, e.g. "Stylus" (slot "StylusToTracker" in the pose table)
    std::vector<uint8_t> Rom;    // tool definition (.rom bytes); for a wired tool, empty to use the
                                 // SROM in the tool, or a virtual SROM written over it
    int WiredPort = -1;          // a wired tool's port as PLUS's PortName (channel * 100 + port - 1)
  };

  struct Options {
    std::string Port;                    // serial port, or HOST[:PORT] when Tcp
    bool Tcp = false;                    // the Combined API over TCP (Vega, Lyra; port 8765)
    std::vector<Tool> Tools;
    bool Binary = true;                  // BX:0801 (else TX:0001)
    int MaxBaud = 1228739;               // fastest COMM rate to try
    int RateCode = -1;                   // IRATE 0=20 Hz 1=30 Hz 2=60 Hz; -1 leaves it
    double PollHz = 60.0;
    int CommandTimeoutMs = 5000;         // ordinary commands
    int ProbeTimeoutMs = 150;            // INIT probe before a reset
    int TrackingTimeoutMs = 100;         // TX/BX replies
    int Retries = 3;                     // per command (PVWR chunks, TX/BX polls)
    int MaxConsecutiveTimeouts = 10;     // then the device is considered gone
    double ReconnectInitialSeconds = 0.1;
    double ReconnectMaxSeconds = 2.0;
    /// Makes the transport (tests inject one; default: MakeSerialTransport(Port)).
    std::function<std::unique_ptr<NdiTransport>()> TransportFactory;
  };

  enum class State : int { Stopped = 0, Connecting, Configuring, Tracking, Disconnected };
  static const char* StateName(State state);

  struct Statistics {
    uint64_t Frames = 0;          // tracking replies parsed
    uint64_t CrcErrors = 0;
    uint64_t Timeouts = 0;
    uint64_t FrameGaps = 0;       // frames the tracker produced that we never saw
    uint64_t DeviceErrors = 0;
    uint64_t MalformedReplies = 0;
    uint64_t Connections = 0;     // successful set-ups (1 + reconnects)
    uint64_t Resets = 0;          // break or RESET used
    uint64_t LateReplies = 0;     // replies that arrived after their poll timed out (still used)
    double ThreadCpuSeconds = 0;  // CPU time of the I/O thread
  };

  explicit NdiTracker(Options options);
  ~NdiTracker() override;
  /// From a configuration: Address = the port, ToolFiles, options "rate" (20|30|60 Hz) and
  /// "text" (1: TX instead of BX). Throws std::invalid_argument / std::runtime_error.
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config);
  /// The same over TCP: Address = HOST[:PORT] (port 8765 by default).
  static std::unique_ptr<PoseSource> CreateTcp(const PoseSourceConfig& config);

  /// Starts the I/O thread (returns at once; watch GetState()).
  bool Start(std::string& error) override;
  using PoseSource::Start;
  /// Stops tracking (TSTOP, PHF, COMM back to 9600) and joins the thread.
  void Stop() override;
  const ToolPoseTable& Poses() const override { return this->Table; }
  bool Connected() const override { return this->GetState() == State::Tracking; }
  std::string StatusText() const override;
  nlohmann::json StatisticsJson() const override;

  State GetState() const { return static_cast<State>(this->CurrentState.load(std::memory_order_acquire)); }
  Statistics GetStatistics() const;
  std::string LastError() const { return this->Worker.LastError(); }
  std::string FirmwareVersion() const;
  int NegotiatedBaud() const { return this->Baud.load(); }

 private:
  void Run();
  bool Connect();
  bool Configure();
  /// The version (VER), the fastest baud both ends can do (COMM) and the frame rate (IRATE).
  bool NegotiateLink();
  void TrackLoop();
  /// Parses the frame in Rx and publishes its poses. False: the device must be set up again.
  bool ProcessTrackingFrame(uint32_t& lastFrame);
  void Shutdown();
  bool Reset();
  /// Sends a command and waits for its ASCII reply. Retries on timeout/CRC error (retries>0).
  ndi::ParseResult Command(const char* name, const char* args, int timeoutMs, int retries);
  /// Reads one frame into Frame/FrameLength. 0 ok, 1 timeout, -1 transport gone, 2 resync.
  int ReadFrame(int timeoutMs);
  void Fail(const std::string& message) { this->Worker.Fail(message); }
  /// Stop requested (and not in the middle of the stop commands themselves).
  bool Stopping() const { return this->Worker.StopRequested() && !this->ShuttingDown; }
  void SetState(State s) { this->CurrentState.store(static_cast<int>(s), std::memory_order_release); }
  void UpdateCpu();
  std::unique_ptr<NdiTransport> MakeTransport() const;

  Options Opts;
  std::unique_ptr<NdiTransport> Transport;
  ToolPoseTable Table;
  WorkerThread Worker;
  std::atomic<int> CurrentState{0};
  std::atomic<int> Baud{9600};

  // statistics (written by the I/O thread)
  std::atomic<uint64_t> Frames{0}, CrcErrors{0}, Timeouts{0}, FrameGaps{0}, DeviceErrors{0}, Malformed{0},
      Connections{0}, Resets{0}, LateReplies{0};
  std::atomic<double> CpuSeconds{0};
  mutable std::mutex VersionMutex;  // firmware text (set once per connection)
  std::string Version;

  // I/O thread only
  bool ShuttingDown = false;
  uint8_t Rx[16384];
  size_t RxLength = 0;
  size_t FrameLength = 0;  // the frame at Rx[0..FrameLength)
  const char* Payload = nullptr;
  size_t PayloadLength = 0;
  int HandleSlot[256];
  uint32_t LastFrame[256];
  std::vector<uint8_t> HandlesToFree;  // loaded from a definition we sent (PVWR): freed at stop, as PLUS does
  ndi::TrackingReply Reply;
};

}  // namespace rp
