#pragma once
// The NDI Combined API as a simulated Polaris answers it (rpPolarisSimulator.h): port handles
// (wireless ones a host requests, wired ones from power-on), tool definitions written and
// initialized, tracking started and stopped, TX/BX replies with noisy poses and the port and
// frame flags, and the ASCII/binary framing with CRCs. One handler per command, as PLUS's and
// NDI's simulators have. Runs on the simulator thread; GetCounters on any.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "rpPolarisSimulatorTools.h"

namespace rp {

/// What a simulated Polaris has seen and is doing (PolarisSimulator::Counters).
struct PolarisSimulatorCounters {
  uint64_t Commands = 0, Breaks = 0, Resets = 0, TrackingReplies = 0, CrcErrorsSeen = 0;
  int Baud = 9600;
  bool Tracking = false;
  int LoadedTools = 0;
};

class PolarisSimulatorDevice {
 public:
  /// Where replies go: the bytes and whether they are an ASCII reply (PolarisSimulatorLink::Send).
  using Sender = std::function<void(uint8_t* data, size_t length, bool ascii)>;
  PolarisSimulatorDevice(const PolarisSimulatorOptions& options, PolarisSimulatorTools& tools, Sender send);

  /// Powered on at `startTime` (SteadySeconds()): the state a device has after power-on.
  void PowerOn(double startTime);
  /// Back to the power-on state (no handles but the wired ports', not initialized, 9600 baud).
  void PowerOnReset();
  /// A serial break: counted; with `accept`, a power-on reset answered "RESET".
  void Break(bool accept);
  /// Bytes from the host; every complete command (up to CR) is answered.
  void Receive(const char* data, size_t length);
  /// What the host sent so far and no command yet: void (a new host connected).
  void ClearInput() { this->Input.clear(); }
  double Now() const;  // seconds since power-on
  PolarisSimulatorCounters GetCounters() const;

 private:
  struct Handle {
    int Number = 0;
    std::vector<uint8_t> Rom = std::vector<uint8_t>(1024, 0);
    uint16_t ChunksWritten = 0;
    bool Initialized = false, Enabled = false;
    int Tool = -1;       // index into the tools, -1 for an unknown definition
    int WiredTool = -1;  // the tool plugged into this handle's wired port, -1 for a wireless handle
    uint32_t LastFrame = 0;
  };
  void HandleCommand(const char* line, size_t length);
  // One handler per NDI command (the table in the .cxx); each replies through Reply/ReplyError.
  using CommandHandler = void (PolarisSimulatorDevice::*)(const std::string& name, const std::string& args);
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
  void BuildTracking(bool binary);
  Handle* FindHandle(const char* hex);
  /// A wired port's handle holds the SROM of the tool plugged into it (h.WiredTool).
  void LoadPluggedSrom(Handle& h) const;
  uint32_t CurrentFrame() const;

  const PolarisSimulatorOptions& Opts;
  PolarisSimulatorTools& Tools;
  Sender Send;
  double StartTime = 0;
  std::vector<Handle> Handles;
  std::string Input;
  bool Initialized = false, Tracking = false;
  double TrackingStart = 0;
  double Rate = 60;
  int Baud = 9600;
  std::mt19937 Rng;
  mutable std::mutex CountersMutex;
  PolarisSimulatorCounters Count;
};

}  // namespace rp
