#pragma once
// The tools a simulated NDI Polaris sees (rpPolarisSimulator.h): the definitions it was given
// (wireless, or plugged into a wired port), the tools it makes from ROMs a host uploads, their
// scripted poses, whether enough markers face the camera, and the faults injected on them
// (occluded, out of volume). Thread-safe for the callers outside the simulator thread; only the
// simulator thread adds tools (a new ROM) and reads them by index without the lock.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rpNdiRom.h"
#include "rpToolDefinition.h"

namespace rp {

/// What a simulated Polaris is built with (PolarisSimulator::Options).
struct PolarisSimulatorOptions {
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

class PolarisSimulatorTools {
 public:
  struct Tool {
    ToolDefinition Definition;
    rom::Definition Rom;  // geometry as the camera sees it: normals, minimum markers, maximum angle
    std::atomic<bool> Occluded{false}, OutOfVolume{false};
    int WiredPort = -1;   // plugged into this wired port (PLUS's PortName numbering), -1 wireless
  };

  /// A tool given before the simulator starts (`wiredPort` >= 0: plugged into that port).
  void Add(const ToolDefinition& tool, int wiredPort);
  /// The wireless tool whose definition `rom` is; a definition none matches becomes a tool of
  /// its own (its geometry from the ROM, standing still in the volume beside `volumeCenter`).
  /// -1 when the ROM does not read. Simulator thread.
  int ForRom(const std::vector<uint8_t>& rom, const double volumeCenter[3]);
  /// By index (from Add order, then ForRom). Simulator thread, no lock.
  const Tool& operator[](size_t index) const { return *this->Tools[index]; }
  size_t Size() const { return this->Tools.size(); }

  void SetOccluded(const std::string& toolName, bool occluded);
  void SetOutOfVolume(const std::string& toolName, bool outOfVolume);
  /// The tool's true pose (no noise) at time t, row-major 4x4 ToolToTracker.
  bool TruePose(const std::string& toolName, double t, double m[16]) const;
  std::vector<std::string> Names() const;
  std::vector<std::array<double, 3>> Markers(const std::string& toolName) const;
  /// Enough markers of the tool face the camera at pose m (row-major ToolToTracker).
  static bool MarkersVisible(const Tool& tool, const double m[16]);

 private:
  std::vector<std::unique_ptr<Tool>> Tools;
  mutable std::mutex Mutex;  // Tools grows on the simulator thread (PINIT of a new ROM)
};

}  // namespace rp
