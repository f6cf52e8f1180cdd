#pragma once
// A simulated NDI Polaris speaking the Combined API on a pseudo-terminal, or over TCP on
// 127.0.0.1 as a Polaris Vega/Lyra does on Ethernet, for tests, demos and the `roboplan
// polaris-sim` command. A tool definition uploaded with PVWR that matches none of the tools it
// was given becomes a tool of its own, its geometry and part number from the ROM (standing
// still in the volume), as a real camera tracks any tool whose ROM it is sent. Tools follow
// scripted trajectories with measurement noise; faults (occlusion, out of volume, CRC errors,
// slow and dropped replies, unplug) are injected through thread-safe calls. The serial break
// arrives out of band (DeliverBreak(), or a datagram on the unix socket `<link>.break` when a
// link path is given).
//
// Its parts, one job each: the tools in the camera's view (rpPolarisSimulatorTools.h), the
// cable with its faults (rpPolarisSimulatorLink.h), the Combined API state machine
// (rpPolarisSimulatorDevice.h); this class owns them and the thread that runs them.
#include <array>
#include <string>
#include <vector>

#include "rpPolarisSimulatorDevice.h"
#include "rpPolarisSimulatorLink.h"
#include "rpPolarisSimulatorTools.h"
#include "rpToolDefinition.h"
#include "rpWorkerThread.h"

namespace rp {

/// Resources/Tools/*.json, sorted: the tools a simulator carries unless told otherwise.
std::vector<std::string> DefaultToolFiles();

class PolarisSimulator {
 public:
  using Options = PolarisSimulatorOptions;
  using Counters = PolarisSimulatorCounters;

  PolarisSimulator();
  explicit PolarisSimulator(Options options);
  ~PolarisSimulator();

  /// A tool it tracks. `wiredPort` >= 0 plugs it into that wired port (numbered as PLUS's
  /// PortName: channel * 100 + port - 1), its definition then being the SROM inside the tool: the
  /// device gives the port a handle at power-on, PHINF tells where it is plugged, and a host may
  /// write a virtual SROM over it. Call before Start.
  void AddTool(const ToolDefinition& tool, int wiredPort = -1) { this->Tools.Add(tool, wiredPort); }
  bool Start(std::string& error);
  void Stop();
  /// What a driver opens: the link when one was given, the pty slave otherwise; over TCP
  /// "127.0.0.1:PORT".
  std::string PortPath() const { return this->Link.PortPath(); }
  bool Tcp() const { return this->Link.Tcp(); }
  /// The TCP port served (after Start), 0 on a pty.
  int TcpPort() const { return this->Link.TcpPort(); }
  std::string SlavePath() const { return this->Link.SlavePath(); }

  // ---- fault injection (any thread)
  void SetOccluded(const std::string& toolName, bool occluded) { this->Tools.SetOccluded(toolName, occluded); }
  void SetOutOfVolume(const std::string& toolName, bool outOfVolume) {
    this->Tools.SetOutOfVolume(toolName, outOfVolume);
  }
  void CorruptNextReplies(int count) { this->Link.CorruptNextReplies(count); }
  void DropNextReplies(int count) { this->Link.DropNextReplies(count); }
  void SetReplyDelay(int milliseconds) { this->Link.SetReplyDelay(milliseconds); }
  void DeliverBreak() { this->Link.DeliverBreak(); }
  /// Pulls the cable: closes the pty (the host reads EIO) and removes the link (the port is gone
  /// until Replug, so a host retrying it cannot open a recycled pty number); over TCP closes the
  /// connection and stops listening (connections are refused until Replug).
  void Unplug() { this->Link.Unplug(); }
  /// Plugs it back: a new pty (the link, when given, is re-pointed) in power-on state.
  bool Replug(std::string& error) { return this->Link.Replug(error); }

  Counters GetCounters() const { return this->Device.GetCounters(); }
  /// The tool's true pose (no noise) at time t since start, row-major 4x4 ToolToTracker.
  bool TruePose(const std::string& toolName, double t, double m[16]) const {
    return this->Tools.TruePose(toolName, t, m);
  }
  /// Names of the tools it tracks: those given, then those made from uploaded ROMs (part number).
  std::vector<std::string> ToolNames() const { return this->Tools.Names(); }
  /// The markers of a tool (from its definition or its ROM); empty when unknown.
  std::vector<std::array<double, 3>> ToolMarkers(const std::string& toolName) const {
    return this->Tools.Markers(toolName);
  }
  double Now() const { return this->Device.Now(); }  // seconds since Start

 private:
  void Run();

  Options Opts;
  PolarisSimulatorTools Tools;
  PolarisSimulatorLink Link;
  PolarisSimulatorDevice Device;
  WorkerThread Worker;
};

}  // namespace rp
