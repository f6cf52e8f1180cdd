#pragma once
// What `roboplan track --plus-config` runs of a PLUS configuration: the pose source for its NDI
// tracker (serial, TCP, or the simulator carrying the configuration's own ROMs), the transform
// repository (CoordinateDefinitions' fixed transforms + one live <Tool>To<ToolReferenceFrame>
// per tool), and the relay that turns the tracker's newest poses into the transforms the
// PlusOpenIGTLinkServer section names (e.g. StylusTipToReference), published into a pose table
// that the OpenIGTLink server streams.
#include <memory>
#include <string>
#include <vector>

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
  TransformRepository& Repository() { return this->Repo; }
  const std::vector<plus::Refusal>& Refused() const { return this->Problems; }

 private:
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
