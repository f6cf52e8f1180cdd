#ifndef vtkRPTrackingLogic_h
#define vtkRPTrackingLogic_h
// The bridge between pose sources and the scene. A source (rp::PoseSource: the serial driver,
// the OpenIGTLink client, a replay, the simulator; made by the registry from a configuration)
// runs its own I/O thread and publishes into lock-free tables. UpdateNodes(), called on the
// main thread when a source signals new data (its ReadyFd) or by a display-rate timer, copies
// the newest pose of every tool into its vtkRPTrackedToolNode and the newest image of every
// image stream into its vtkRPScalarVolumeNode, in one batch; marks tools stale after a
// timeout; and keeps per-tool counts (OK / MISSING / out of volume), rate and latency. Nodes
// are looked up by ID at every update, so deleting a node that receives data is safe (it is
// re-created when data arrives again, as Slicer's OpenIGTLink connector does, unless
// AutoCreateNodes is off).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <vtkObject.h>

#include "rpPivotCalibration.h"
#include "rpPlusPhantomRegistration.h"
#include "rpPoseSource.h"
#include "rpToolPose.h"

class vtkRPScene;
class vtkRPTrackedToolNode;
class vtkRPLinearTransformNode;
class vtkRPScalarVolumeNode;

namespace rp {
class ImageTable;
struct ImageFrame;
class PolarisSimulator;
struct PolarisSimulatorOptions;
struct ToolDefinition;
namespace rom {
struct Definition;
}
}  // namespace rp

class vtkRPTrackingLogic : public vtkObject {
 public:
  static vtkRPTrackingLogic* New();
  vtkTypeMacro(vtkRPTrackingLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene);
  vtkRPScene* GetScene() const { return this->Scene; }

  /// Creates a source from the registry and starts it. Returns its id, or -1 with the reason.
  int Connect(const rp::PoseSourceConfig& config, std::string& error);
  /// Takes a source made elsewhere and starts it. Returns its id, or -1 with the reason.
  int AddSource(std::unique_ptr<rp::PoseSource> source, std::string& error);
  /// The source of an id (nullptr for unknown ids and plain tables).
  rp::PoseSource* GetSource(int id) const;
  /// Stops and deletes a source (or forgets a table). Its nodes stay in the scene.
  void RemoveSource(int id);
  /// Tables written by a thread of the caller's; node name = slot name (a transform name such
  /// as StylusToTracker, or an image's device name). They must outlive the logic or be removed
  /// first. Returns an id.
  int AddPoseTable(const rp::ToolPoseTable* poses, const rp::ImageTable* images = nullptr);
  /// File descriptors that become readable when a source has new data (for poll or a
  /// QSocketNotifier); UpdateNodes clears them.
  std::vector<int> GetReadyFds() const;

  /// Seconds without a fresh pose before a tool is shown as stale.
  vtkSetMacro(StaleTimeout, double);
  vtkGetMacro(StaleTimeout, double);
  vtkSetMacro(AutoCreateNodes, bool);
  vtkGetMacro(AutoCreateNodes, bool);
  /// When set (e.g. "ReferenceToTracker"), every other tool also gets a <Tool>ToReference node.
  void SetReferenceNodeName(const std::string& name) { this->ReferenceName = name; }

  /// Main thread: copy the newest poses and images into nodes. `now` in SteadySeconds().
  /// Returns the number of nodes modified.
  int UpdateNodes(double now);

  struct ToolStatistics {
    std::string NodeName, NodeID;
    int Status = 0;                   // vtkRPTrackedToolNode::Status
    rp::ToolPoseTable::StateCounts Frames;  // every frame the source published, by state
    uint64_t Dropped = 0;             // published but overwritten before an update saw them
    double RateHz = 0;                // fresh poses per second (running estimate)
    double LatencySeconds = 0;        // receive → node update, last fresh pose
    double MeanLatencySeconds = 0, MaxLatencySeconds = 0;
    double ErrorRMS = -1;
    bool HasPose = false;             // a pose with data (OK or out of volume) was seen
    rp::ToolPose LastPose;            // the newest such pose
  };
  std::vector<ToolStatistics> GetToolStatistics() const;

  struct ImageStatistics {
    std::string NodeName, NodeID;
    uint64_t Frames = 0, Shown = 0;   // published by the source, copied into the node
    int Dimensions[3] = {0, 0, 0};
    double LatencySeconds = 0;        // receive → node update, last frame
  };
  std::vector<ImageStatistics> GetImageStatistics() const;

  /// Pivot calibration of a stylus from its poses (rp::PivotCalibrate: only OK poses count; RMSE
  /// above thresholdMm rejects; the stylus must turn minSpreadDeg). When it solves (Valid, even if
  /// rejected, so that a user sees it) and the logic has a scene, StylusTipToStylus is applied
  /// under the stylus node (ApplyPivotCalibration; `tip` receives it). The panel, `roboplan pivot`
  /// and the demo calibrate through this one function.
  rp::PivotResult CalibratePivot(const std::vector<rp::ToolPose>& poses, const std::string& stylusNodeName,
                                 double thresholdMm = 1.0, double minSpreadDeg = 10.0,
                                 vtkRPLinearTransformNode** tip = nullptr);
  /// StylusTipToStylus as a child transform of the stylus node (created or updated), with the
  /// calibration's RMSE in its PivotCalibrationRMSEAttribute().
  vtkRPLinearTransformNode* ApplyPivotCalibration(const rp::PivotResult& result, const std::string& stylusNodeName,
                                                  const std::string& tipNodeName = "StylusTipToStylus");
  static const char* PivotCalibrationRMSEAttribute() { return "PivotCalibration.RMSE"; }

  /// Phantom registration from a PLUS recording, as fCal's landmark detection: reads the PLUS
  /// configuration (`config` receives it) and the tracked-frame recording, finds the landmarks
  /// (rp::RegisterPhantomFromRecording) and fits PhantomToReference. A file that cannot be read
  /// gives Ok false and its reason in Error. When it solves and the logic has a scene, the result
  /// is applied (ApplyPhantomRegistration; `applied` receives it). `roboplan phantom-registration`
  /// registers through this function.
  rp::PhantomRegistrationResult RegisterPhantom(const std::string& recordingPath, const std::string& configPath,
                                                rp::LandmarkDetectionMethod method, rp::PlusPhantomConfiguration& config,
                                                vtkRPLinearTransformNode** applied = nullptr);
  /// <Phantom>To<Reference> (the configuration's frame names) as a transform node (created or
  /// updated) under the reference tool's node when the scene has one, with the FRE in its
  /// PhantomRegistrationFREAttribute().
  vtkRPLinearTransformNode* ApplyPhantomRegistration(const rp::PhantomRegistrationResult& result,
                                                     const rp::PlusPhantomConfiguration& config);
  static const char* PhantomRegistrationFREAttribute() { return "PhantomRegistration.FRE"; }

  /// A tool definition file: an NDI .rom (checksum verified) or a RoboPlan tool (.json, whose
  /// .rom is made), parsed into `definition` with its .rom bytes in `rom` (`roboplan tool-info`).
  /// False with `error` naming the file and the problem.
  static bool ReadToolDefinitionFile(const std::string& path, rp::rom::Definition& definition,
                                     std::vector<uint8_t>& rom, std::string& error);
  /// A simulated NDI Polaris (a pseudo-terminal, or a Vega over TCP when options.TcpPort >= 0)
  /// tracking `tools`, each passive (port -1) or plugged into wired port `ports[i]` (PLUS's
  /// PortName numbering), started (`roboplan polaris-sim`; Connect() opens its port like a real
  /// camera's). nullptr with `error` when it cannot start.
  static std::unique_ptr<rp::PolarisSimulator> StartSimulatedPolaris(const rp::PolarisSimulatorOptions& options,
                                                                     const std::vector<rp::ToolDefinition>& tools,
                                                                     const std::vector<int>& ports, std::string& error);

 protected:
  vtkRPTrackingLogic();
  ~vtkRPTrackingLogic() override;

 private:
  vtkRPTrackingLogic(const vtkRPTrackingLogic&) = delete;
  void operator=(const vtkRPTrackingLogic&) = delete;

  struct Tool {
    std::string NodeName, NodeID;
    int Status = 0;
    double LastFreshTime = 0, RateHz = 0, Latency = 0, LatencySum = 0, MaxLatency = 0, ErrorRMS = -1;
    uint64_t LastReceived = 0, Updates = 0;
    rp::ToolPose Pose;                // newest (any state)
    rp::ToolPose ValidPose;           // newest with data (OK, out of volume)
    bool HasPose = false, HasValidPose = false;
  };
  struct Image {
    std::string NodeName, NodeID;
    uint64_t Published = 0, Shown = 0;
    int Dimensions[3] = {0, 0, 0};
    double Latency = 0;
  };
  struct Source {
    std::unique_ptr<rp::PoseSource> Owned;  // null for plain tables
    const rp::ToolPoseTable* Table = nullptr;
    const rp::ImageTable* Images = nullptr;
    rp::ToolPoseReader Reader;
    std::vector<Tool> Tools;    // by slot
    std::vector<Image> Streams;  // by image slot
  };
  vtkRPTrackedToolNode* NodeFor(Tool& tool);
  // The transform node `name` (created when the scene has none) set to `toParent` (row-major)
  // and, when the scene has a transform node `parentName`, under it.
  vtkRPLinearTransformNode* SetTransformUnder(const std::string& name, const double toParent[16],
                                              const std::string& parentName);
  vtkRPScalarVolumeNode* VolumeFor(Image& image);
  void WriteNode(vtkRPTrackedToolNode* node, const rp::ToolPose& pose, int status, double errorRMS);
  int UpdateTools(Source& source, double now, std::vector<const Tool*>& all, std::vector<const Tool*>& changed,
                  const Tool*& reference);
  int UpdateImages(Source& source, double now);
  void WriteVolume(vtkRPScalarVolumeNode* node, const rp::ImageFrame& frame);

  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
  std::map<int, Source> Sources;
  int NextSourceId = 1;
  double StaleTimeout = 0.5;
  bool AutoCreateNodes = true;
  std::string ReferenceName;
  std::map<std::string, std::string> DerivedNodeIDs;
};

#endif
