#pragma once
// A simulated NDI Polaris speaking the Combined API on a pseudo-terminal, or over TCP on
// 127.0.0.1 as a Polaris Vega/Lyra does on Ethernet, for tests, demos and the `roboplan
// polaris-sim` command. A tool definition uploaded with PVWR that matches none of the tools it
// was given becomes a tool of its own, its geometry and part number from the ROM (standing
// still in the volume), as a real camera tracks any tool whose ROM it is sent. Tools follow scripted trajectories with measurement
// noise; faults (occlusion, out of volume, CRC errors, slow and dropped replies, unplug) are
// injected through thread-safe calls. The serial break arrives out of band (DeliverBreak(), or
// a datagram on the unix socket `<link>.break` when a link path is given).
#include <array>
#include <atomic>
#include <memory>
#include <cstdint>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "rpToolDefinition.h"
#include "rpWorkerThread.h"

namespace rp {

/// Resources/Tools/*.json, sorted: the tools a simulator carries unless told otherwise.
std::vector<std::string> DefaultToolFiles();

class PolarisSimulator {
 public:
  struct Options {
    double FrameRate = 60.0;        // 20 (Vicra) or 60 (Spectra); IRATE can change it
    double NoiseMm = 0.0;           // translation noise, standard deviation (mm)
    double NoiseDeg = 0.0;          // rotation noise, standard deviation (deg)
    double VolumeRadius = 1200.0;   // out of volume beyond this distance from VolumeCenter
    double VolumeCenter[3] = {0, 0, -1500};
    std::string LinkPath;           // symlink to the pty (kept across replug) + "<link>.break" socket
    uint32_t Seed = 1;
    bool AcceptBreak = true;        // false: ignore breaks (host must use the RESET command)
    int TcpPort = -1;               // >= 0: serve TCP on 127.0.0.1 instead of a pty (0: any free port)
    /// A tool is MISSING when fewer than its ROM's minimum markers face the camera (at the
    /// tracker origin) within the ROM's maximum marker angle (its marker normals).
    bool MarkerVisibility = false;
  };

  struct Counters {
    uint64_t Commands = 0, Breaks = 0, Resets = 0, TrackingReplies = 0, CrcErrorsSeen = 0;
    int Baud = 9600;
    bool Tracking = false;
    int LoadedTools = 0;
  };

  PolarisSimulator();
  explicit PolarisSimulator(Options options);
  ~PolarisSimulator();

  /// A tool it tracks. `wiredPort` >= 0 plugs it into that wired port (numbered as PLUS's
  /// PortName: channel * 100 + port - 1), its definition then being the SROM inside the tool: the
  /// device gives the port a handle at power-on, PHINF tells where it is plugged, and a host may
  /// write a virtual SROM over it. Call before Start.
  void AddTool(const ToolDefinition& tool, int wiredPort = -1);
  bool Start(std::string& error);
  void Stop();
  /// What a driver opens: the link when one was given, the pty slave otherwise; over TCP
  /// "127.0.0.1:PORT".
  std::string PortPath() const;
  bool Tcp() const { return this->Opts.TcpPort >= 0; }
  /// The TCP port served (after Start), 0 on a pty.
  int TcpPort() const { return this->BoundPort.load(); }
  std::string SlavePath() const;

  // ---- fault injection (any thread)
  void SetOccluded(const std::string& toolName, bool occluded);
  void SetOutOfVolume(const std::string& toolName, bool outOfVolume);
  void CorruptNextReplies(int count) { this->CrcFaults += count; }
  void DropNextReplies(int count) { this->Drops += count; }
  void SetReplyDelay(int milliseconds) { this->DelayMs = milliseconds; }
  void DeliverBreak() { this->BreakPending = true; }
  /// Pulls the cable: closes the pty (the host reads EIO) and removes the link (the port is gone
  /// until Replug, so a host retrying it cannot open a recycled pty number); over TCP closes the
  /// connection and stops listening (connections are refused until Replug).
  void Unplug();
  /// Plugs it back: a new pty (the link, when given, is re-pointed) in power-on state.
  bool Replug(std::string& error);

  Counters GetCounters() const;
  /// The tool's true pose (no noise) at time t since start, row-major 4x4 ToolToTracker.
  bool TruePose(const std::string& toolName, double t, double m[16]) const;
  /// Names of the tools it tracks: those given, then those made from uploaded ROMs (part number).
  std::vector<std::string> ToolNames() const;
  /// The markers of a tool (from its definition or its ROM); empty when unknown.
  std::vector<std::array<double, 3>> ToolMarkers(const std::string& toolName) const;
  double Now() const;  // seconds since Start

 private:
  struct Handle {
    int Number = 0;
    std::vector<uint8_t> Rom = std::vector<uint8_t>(1024, 0);
    uint16_t ChunksWritten = 0;
    bool Initialized = false, Enabled = false;
    int Tool = -1;  // index into Tools, -1 for an unknown definition
    int WiredTool = -1;  // the tool plugged into this handle's wired port, -1 for a wireless handle
    uint32_t LastFrame = 0;
  };
  struct ToolRuntime {
    ToolDefinition Definition;
    rom::Definition Rom;  // geometry as the camera sees it: normals, minimum markers, maximum angle
    std::atomic<bool> Occluded{false}, OutOfVolume{false};
    int WiredPort = -1;   // plugged into this wired port (PLUS's PortName numbering), -1 wireless
  };
  /// Enough markers of the tool face the camera at pose m (row-major ToolToTracker).
  static bool MarkersVisible(const ToolRuntime& tool, const double m[16]);

  void Run();
  bool OpenPty(std::string& error);
  void ClosePty();
  bool OpenListener(std::string& error);
  void AcceptClient();
  int ToolForRom(const std::vector<uint8_t>& rom);
  void PowerOnReset();
  /// A wired port's handle holds the SROM of the tool plugged into it (h.WiredTool).
  void LoadPluggedSrom(Handle& h) const;
  void HandleCommand(const char* line, size_t length);
  // One handler per NDI command (the table in the .cxx); each replies through Reply/ReplyError.
  using CommandHandler = void (PolarisSimulator::*)(const std::string& name, const std::string& args);
  struct CommandEntry;
  static const CommandEntry CommandTable[];
  /// The command's name and arguments; false (an error replied) when a CRC after ':' is short or wrong.
  bool SplitCommand(std::string text, std::string& name, std::string& args);
  /// The handle named by the first two hex digits of `args`; null (an error replied) when there is none.
  Handle* CommandHandle(const std::string& args);
  void OnReset(const std::string& name, const std::string& args);
  void OnInit(const std::string& name, const std::string& args);
  void OnGetInfo(const std::string& name, const std::string& args);
  void OnVersion(const std::string& name, const std::string& args);
  void OnComm(const std::string& name, const std::string& args);
  void OnIrate(const std::string& name, const std::string& args);
  void OnAcknowledge(const std::string& name, const std::string& args);
  void OnPhsr(const std::string& name, const std::string& args);
  void OnPhrq(const std::string& name, const std::string& args);
  void OnPhf(const std::string& name, const std::string& args);
  void OnPvwr(const std::string& name, const std::string& args);
  void OnPinit(const std::string& name, const std::string& args);
  void OnPhinf(const std::string& name, const std::string& args);
  void OnPena(const std::string& name, const std::string& args);
  void OnPdis(const std::string& name, const std::string& args);
  void OnTstart(const std::string& name, const std::string& args);
  void OnTstop(const std::string& name, const std::string& args);
  void OnTracking(const std::string& name, const std::string& args);
  void Reply(const char* payload);
  void ReplyError(int code);
  void ReplyBinary(const uint8_t* body, size_t length);
  void SendRaw(uint8_t* data, size_t length, bool asciiCrcAt);
  void BuildTracking(bool binary);
  Handle* FindHandle(const char* hex);
  uint32_t CurrentFrame() const;

  Options Opts;
  std::vector<std::unique_ptr<ToolRuntime>> Tools;
  mutable std::mutex ToolsMutex;  // Tools grows on the simulator thread (PINIT of a new ROM)
  WorkerThread Worker;
  std::atomic<bool> BreakPending{false}, Unplugged{false};
  std::atomic<int> CrcFaults{0}, Drops{0}, DelayMs{0};
  mutable std::mutex PtyMutex;  // guards the fds and paths against Unplug/Replug (not hot)
  int MasterFd = -1, KeepSlaveFd = -1, BreakSocketFd = -1, ListenFd = -1;  // MasterFd: the TCP client over TCP
  std::atomic<int> BoundPort{0};
  std::string Slave;
  double StartTime = 0;

  // device state (simulator thread only, Counters mirrored under CountersMutex)
  std::vector<Handle> Handles;
  std::string Input;
  bool Initialized = false, Tracking = false;
  double TrackingStart = 0;
  double Rate = 60;
  int Baud = 9600;
  std::mt19937 Rng;
  mutable std::mutex CountersMutex;
  Counters Count;
};

}  // namespace rp
