#include "rpPlusTracking.h"

#include <stdexcept>

#include <Eigen/Core>

#include "rpNdiTracker.h"
#include "rpSimulatedPolaris.h"
#include "rpToolDefinition.h"
#include "rpTransformNames.h"

namespace rp {

namespace {
Eigen::Matrix4d RowMajor(const double m[16]) {
  Eigen::Matrix4d out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = m[4 * r + c];
  return out;
}
}  // namespace

void BuildRepository(const plus::Configuration& c, const plus::NdiTracker* tracker, TransformRepository& repo,
                     std::vector<int>& liveEdges, std::vector<plus::Refusal>& refused) {
  std::string error;
  for (const plus::FixedTransform& t : c.Transforms)
    if (!repo.SetFixed(t.From, t.To, RowMajor(t.Matrix), error)) refused.push_back({"Transform " + t.From + "To" + t.To, error});
  liveEdges.clear();
  if (!tracker) return;
  for (const plus::Tool& tool : tracker->Tools) {
    const int edge = repo.DeclareLive(tool.Id, tracker->ToolReferenceFrame, error);
    if (edge < 0) refused.push_back({"tool " + tool.Id, error});
    liveEdges.push_back(edge);
  }
}

nlohmann::json ServedTransformsJson(const plus::Configuration& c, const plus::NdiTracker* tracker,
                                    std::vector<plus::Refusal>* refused) {
  TransformRepository repo;
  std::vector<int> edges;
  std::vector<plus::Refusal> problems;
  BuildRepository(c, tracker, repo, edges, problems);
  nlohmann::json served = nlohmann::json::array();
  for (const plus::TransformName& n : c.OpenIGTLinkServer.TransformNames) {
    std::string from = n.From, to = n.To, error;
    if ((from.empty() || to.empty()) && !SplitTransformName(n.Name, from, to, error)) {
      problems.push_back({"served transform " + n.Name, error});
      continue;
    }
    const std::string chain = repo.Describe(repo.Prepare(from, to));
    if (chain.empty())
      problems.push_back({"served transform " + n.Name,
                          "cannot be computed: " + from + " and " + to + " are not connected by the tools and CoordinateDefinitions"});
    else served.push_back({{"name", n.Name}, {"from", from}, {"to", to}, {"chain", chain}});
  }
  if (refused) refused->insert(refused->end(), problems.begin(), problems.end());
  return served;
}

std::unique_ptr<PoseSource> MakePlusPoseSource(const plus::NdiTracker& tracker, const std::string& address, bool simulate) {
  if (tracker.Tools.empty()) throw std::invalid_argument("tracker " + tracker.Id + " has no tool RoboPlan can load");
  std::vector<ToolDefinition> tools;
  std::vector<int> wiredPorts;
  for (const plus::Tool& t : tracker.Tools) {
    ToolDefinition tool;
    if (!t.RomPath.empty()) {
      tool = ReadToolFile(t.RomPath);  // markers and part number from the ROM
    } else {  // a wired tool's SROM is in the tool; on the simulator, a four-marker tool in that port
      tool.PartNumber = "WIRED-PORT-" + std::to_string(t.WiredPort);
      tool.Markers = {{0, 0, 0}, {0, 50, 0}, {0, 0, 60}, {40, 40, 0}};
    }
    tool.Name = t.Id;  // PLUS names a tool by its DataSource Id
    tool.Motion.Type = ToolTrajectory::Static;
    tool.Motion.Center[0] = -200.0 + 150.0 * static_cast<double>(tools.size());
    tools.push_back(tool);
    wiredPorts.push_back(t.WiredPort);
  }
  NdiTracker::Options driver;
  if (tracker.AcquisitionRate > 0) {
    driver.PollHz = tracker.AcquisitionRate;  // PLUS polls at AcquisitionRate; the camera keeps its own rate
  }
  if (simulate) {
    PolarisSimulator::Options so;
    so.NoiseMm = 0.05;
    so.NoiseDeg = 0.02;
    return std::make_unique<SimulatedPolaris>(so, tools, driver, wiredPorts);
  }
  for (size_t i = 0; i < tools.size(); ++i) driver.Tools.push_back({tools[i].Name, tools[i].Rom, wiredPorts[i]});
  driver.Tcp = tracker.Tcp();
  driver.Port = !address.empty() ? address
                : tracker.Tcp()  ? tracker.NetworkHostname + ":" + std::to_string(tracker.NetworkPort)
                                 : tracker.SerialDevice;
  if (driver.Port.empty())
    throw std::invalid_argument("tracker " + tracker.Id + " names no serial port or network host: give --serial PORT or --ndi-tcp HOST");
  if (tracker.BaudRate > 0 && !driver.Tcp) driver.MaxBaud = tracker.BaudRate;  // PLUS sets exactly this rate
  return std::make_unique<NdiTracker>(driver);
}

PlusTransformRelay::PlusTransformRelay(const plus::Configuration& c, const plus::NdiTracker& tracker, const ToolPoseTable& live)
    : Live(live) {
  std::vector<int> edges;
  BuildRepository(c, &tracker, this->Repo, edges, this->Problems);
  for (size_t t = 0; t < tracker.Tools.size(); ++t) {
    const std::string slot = ToolToTrackerName(tracker.Tools[t].Id);
    const int index = this->Live.Find(slot.c_str(), slot.size());
    if (index >= 0 && edges[t] >= 0) this->Inputs.push_back({index, edges[t]});
  }
  for (const plus::TransformName& n : c.OpenIGTLinkServer.TransformNames) {
    std::string from = n.From, to = n.To, error;
    if ((from.empty() || to.empty()) && !SplitTransformName(n.Name, from, to, error)) continue;
    const int slot = this->Served.FindOrAdd(n.Name.c_str());
    if (slot >= 0) this->Outputs.push_back({this->Repo.Prepare(from, to), slot});
  }
}

bool PlusTransformRelay::PullInputs(double& newest) noexcept {
  bool fresh = false;
  for (const Input& in : this->Inputs) {
    const auto& sample = this->Reader.Poll(this->Live, in.LiveSlot);
    if (!sample.Fresh) continue;
    fresh = true;
    newest = std::max(newest, sample.Pose.ReceiveTime);
    double m[16];
    sample.Pose.ToMatrix(m);
    const bool valid = sample.Pose.State == ToolState::OK || sample.Pose.State == ToolState::OutOfVolume;
    this->Repo.SetLive(in.Edge, RowMajor(m), valid ? TransformStatus::OK : TransformStatus::Missing);
  }
  return fresh;
}

bool PlusTransformRelay::Get(const std::string& from, const std::string& to, double m[16], ToolState& state) {
  double newest = 0;
  this->PullInputs(newest);
  Eigen::Matrix4d matrix;
  TransformStatus status;
  this->Repo.Get(from, to, matrix, status);
  if (status == TransformStatus::Invalid) return false;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[4 * r + c] = matrix(r, c);
  state = status == TransformStatus::OK ? ToolState::OK : ToolState::Missing;
  return true;
}

bool PlusTransformRelay::Set(const std::string& from, const std::string& to, const double m[16], std::string& error) {
  if (!this->Repo.Update(from, to, RowMajor(m), error)) return false;
  if (this->Mailbox) {
    std::lock_guard<std::mutex> lock(this->Mailbox->Mutex);
    this->Mailbox->Items.emplace_back(from + "|" + to, RowMajor(m));
    this->Mailbox->Pending = true;
  }
  return true;
}

void PlusTransformRelay::ForwardUpdatesTo(PlusTransformRelay& served) {
  this->Mailbox = std::make_shared<Forwarded>();
  served.Mailbox = this->Mailbox;
}

bool PlusTransformRelay::ApplyForwarded() {
  // Only when a command set a transform (rare): the loop otherwise reads one atomic flag.
  if (!this->Mailbox || !this->Mailbox->Pending.exchange(false)) return false;
  std::lock_guard<std::mutex> lock(this->Mailbox->Mutex);
  for (const auto& item : this->Mailbox->Items) {
    const size_t bar = item.first.find('|');
    std::string error;  // the commands' relay accepted it: the same repository accepts it here
    this->Repo.Update(item.first.substr(0, bar), item.first.substr(bar + 1), item.second, error);
  }
  this->Mailbox->Items.clear();
  return true;
}

void PlusTransformRelay::Update() noexcept {
  double newest = 0;
  bool changed = false;
  try {
    changed = this->ApplyForwarded();
  } catch (...) {  // out of memory applying a command's transform: served as before
  }
  if (!this->PullInputs(newest) && !changed) return;
  for (const ServedName& out : this->Outputs) {
    Eigen::Matrix4d matrix;
    TransformStatus status;
    this->Repo.Evaluate(out.Path, matrix, status);
    ToolPose pose;
    double m[16];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[4 * r + c] = matrix(r, c);
    pose.FromMatrix(m);
    pose.Timestamp = pose.ReceiveTime = newest;
    pose.State = status == TransformStatus::OK        ? ToolState::OK
                 : status == TransformStatus::Missing ? ToolState::Missing
                                                      : ToolState::Disabled;  // INVALID: PLUS's TransformStatus name
    this->Served.Publish(out.Slot, pose);
  }
}

}  // namespace rp
