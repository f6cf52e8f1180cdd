#pragma once
// Pose source "simulator": the built-in Polaris simulator on a pseudo-terminal read by the real
// serial driver: the whole serial path without hardware (demos, the panel, fault tests). The
// pty is reached through a link (Address, or a fresh one in the temp folder) so that the
// driver finds the device again after Simulator().Unplug() and Replug().
#include <memory>
#include <string>
#include <vector>

#include "rpNdiTracker.h"
#include "rpPolarisSimulator.h"
#include "rpPoseSource.h"

namespace rp {

class SimulatedPolaris : public PoseSource {
 public:
  /// `wiredPorts[i]` >= 0 plugs tools[i] into that wired port (PLUS's PortName numbering); the
  /// driver then finds it by its port and reads the SROM in the tool.
  SimulatedPolaris(PolarisSimulator::Options simulator, const std::vector<ToolDefinition>& tools, NdiTracker::Options driver,
                   const std::vector<int>& wiredPorts = {});
  ~SimulatedPolaris() override;
  /// Address: the link path (optional); ToolFiles: definitions (.json; default every
  /// Resources/Tools/*.json); options "noise" (mm), "noise-deg", "rate" (20|30|60 Hz).
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config);

  bool Start(std::string& error) override;
  void Stop() override;
  const ToolPoseTable& Poses() const override { return this->Driver.Poses(); }
  bool Connected() const override { return this->Driver.Connected(); }
  std::string StatusText() const override { return "simulated Polaris " + this->Driver.StatusText(); }
  nlohmann::json StatisticsJson() const override;
  int ReadyFd() const override { return this->Driver.ReadyFd(); }
  void DrainReady() const override { this->Driver.DrainReady(); }

  PolarisSimulator& Simulator() { return this->Device; }
  NdiTracker& Tracker() { return this->Driver; }

 private:
  PolarisSimulator Device;
  NdiTracker Driver;
};

}  // namespace rp
