#include "rpSimulatedPolaris.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <stdexcept>

namespace rp {

namespace {
// A link path of our own when none is given: <temp>/roboplan-polaris-<pid>-<n>.
std::string FreshLinkPath() {
  static std::atomic<int> counter{0};
  return (std::filesystem::temp_directory_path() /
          ("roboplan-polaris-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)))
      .string();
}
}  // namespace

SimulatedPolaris::SimulatedPolaris(PolarisSimulator::Options simulator, const std::vector<ToolDefinition>& tools,
                                   NdiTracker::Options driver, const std::vector<int>& wiredPorts)
    : Device([&] {
        if (simulator.LinkPath.empty()) simulator.LinkPath = FreshLinkPath();
        return simulator;
      }()),
      Driver([&] {
        driver.Port = this->Device.PortPath();
        for (size_t i = 0; i < tools.size(); ++i) {
          const int port = i < wiredPorts.size() ? wiredPorts[i] : -1;
          driver.Tools.push_back({tools[i].Name, port >= 0 ? std::vector<uint8_t>{} : tools[i].Rom, port});
        }
        return driver;
      }()) {
  for (size_t i = 0; i < tools.size(); ++i) this->Device.AddTool(tools[i], i < wiredPorts.size() ? wiredPorts[i] : -1);
}

SimulatedPolaris::~SimulatedPolaris() { this->Stop(); }

std::unique_ptr<PoseSource> SimulatedPolaris::Create(const PoseSourceConfig& config) {
  PolarisSimulator::Options so;
  so.LinkPath = config.Address;
  so.NoiseMm = config.Number("noise", 0.05);
  so.NoiseDeg = config.Number("noise-deg", 0.02);
  const double rate = config.Number("rate", 60);
  if (rate != 20 && rate != 30 && rate != 60) throw std::invalid_argument("rate must be 20, 30 or 60 (Hz)");
  so.FrameRate = rate;
  std::vector<ToolDefinition> tools;
  for (const std::string& file : config.ToolFiles.empty() ? DefaultToolFiles() : config.ToolFiles)
    tools.push_back(ReadToolDefinition(file));  // the simulator needs markers and a trajectory: .json
  if (tools.empty()) throw std::runtime_error("no tool definitions found (Resources/Tools/*.json)");
  NdiTracker::Options driver;
  driver.PollHz = rate;
  driver.RateCode = rate == 20 ? 0 : rate == 30 ? 1 : 2;
  return std::make_unique<SimulatedPolaris>(so, tools, driver);
}

bool SimulatedPolaris::Start(std::string& error) {
  if (!this->Device.Start(error)) return false;
  return this->Driver.Start(error);
}

void SimulatedPolaris::Stop() {
  this->Driver.Stop();  // TSTOP, PHF ... before the device goes
  this->Device.Stop();
}

nlohmann::json SimulatedPolaris::StatisticsJson() const {
  nlohmann::json doc = this->Driver.StatisticsJson();
  const auto c = this->Device.GetCounters();
  doc["simulator"] = {{"pty", this->Device.SlavePath()}, {"commands", c.Commands}, {"trackingReplies", c.TrackingReplies}};
  return doc;
}

}  // namespace rp
