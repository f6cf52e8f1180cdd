#pragma once
// What `roboplan track --plus-config` runs of a PLUS configuration: the pose source for its NDI
// tracker (serial, TCP, or the simulator carrying the configuration's own ROMs), the transform
// repository (CoordinateDefinitions' fixed transforms + one live <Tool>To<ToolReferenceFrame>
// per tool), and the relay that turns the tracker's newest poses into the transforms the
// PlusOpenIGTLinkServer section names (e.g. StylusTipToReference), published into a pose table
// that the OpenIGTLink server streams. One thread owns a relay: the server's GetTransform and
// UpdateTransform commands get a relay of their own (Get/Set) reading the same live table.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "rpPlusConfiguration.h"
#include "rpPoseSource.h"
#include "rpToolPose.h"
#include "rpTransformRepository.h"

namespace rp {

/// Fixed transforms of the configuration and a live edge per tool of `tracker` (refusals for
/// what cannot be stored, e.g. a transform that would close a loop). Live edge ids per tool.
void BuildRepository(const plus::Configuration& configuration, const plus::NdiTracker* tracker,
                     TransformRepository& repository, std::vector<int>& liveEdges, std::vector<plus::Refusal>& refused);

/// How each served name is computed from the configuration (its chain, or why it cannot be).
nlohmann::json ServedTransformsJson(const plus::Configuration& configuration, const plus::NdiTracker* tracker,
                                    std::vector<plus::Refusal>* refused = nullptr);

/// The pose source for a configuration's tracker. `address` overrides the port/host of the file
/// ("" keeps it); `simulate`: the built-in Polaris simulator with the tracker's ROMs (tools standing
/// still, 150 mm apart). Throws std::invalid_argument / std::runtime_error naming the problem.
std::unique_ptr<PoseSource> MakePlusPoseSource(const plus::NdiTracker& tracker, const std::string& address, bool simulate);

class PlusTransformRelay {
 public:
  /// `live`: the tracker's pose table (slots <Tool>ToTracker, registered by the time it is made).
  PlusTransformRelay(const plus::Configuration& configuration, const plus::NdiTracker& tracker, const ToolPoseTable& live);
  /// Hot path (no allocation): fresh tool poses into the repository, and when any came, every
  /// served transform into Output() (OK, or MISSING with the last matrix).
  void Update() noexcept;
  const ToolPoseTable& Output() const { return this->Served; }
  /// GetTransform as PLUS answers it: the tools' newest poses read in, then From→To through the
  /// repository (row-major; state OK, MISSING when a live link has no valid pose). False when the
  /// frames are not connected. Allocates on a pair's first call: for commands, not the hot path.
  bool Get(const std::string& from, const std::string& to, double m[16], ToolState& state);
  /// UpdateTransform as PLUS does it (TransformRepository::Update); what this relay accepts is
  /// passed on to the relay given to ForwardUpdatesTo, which applies it at its next Update (so
  /// the served transforms use it, as PlusServer's do).
  bool Set(const std::string& from, const std::string& to, const double m[16], std::string& error);
  /// `served` (owned by another thread) takes this relay's Set transforms from now on.
  void ForwardUpdatesTo(PlusTransformRelay& served);
  TransformRepository& Repository() { return this->Repo; }
  const std::vector<plus::Refusal>& Refused() const { return this->Problems; }

 private:
  bool PullInputs(double& newest) noexcept;  // fresh tool poses into the repository
  bool ApplyForwarded();                      // Set transforms of the commands' relay
  struct Forwarded {                          // commands' thread → the serving relay's thread
    std::mutex Mutex;
    std::atomic<bool> Pending{false};
    std::vector<std::pair<std::string, Eigen::Matrix4d>> Items;  // "From|To", matrix
  };
  std::shared_ptr<Forwarded> Mailbox;
  struct Input {
    int LiveSlot, Edge;
  };
  struct ServedName {
    int Path, Slot;
  };
  const ToolPoseTable& Live;
  ToolPoseReader Reader;
  TransformRepository Repo;
  ToolPoseTable Served;
  std::vector<Input> Inputs;
  std::vector<ServedName> Outputs;
  std::vector<plus::Refusal> Problems;
};

}  // namespace rp
