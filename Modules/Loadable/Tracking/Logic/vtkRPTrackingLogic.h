#ifndef vtkRPTrackingLogic_h
#define vtkRPTrackingLogic_h
// The bridge between tracker I/O threads and the scene. Each pose source (the serial driver,
// the OpenIGTLink client, a replay) publishes into a lock-free ToolPoseTable; UpdateNodes(),
// called by a main-thread timer at display rate, copies the newest pose of every tool into its
// vtkRPTrackedToolNode in one batch (Start/EndModify), marks tools stale after a timeout and
// keeps per-tool rate and dropped counts. Nodes are looked up by ID at every update, so
// deleting a node that receives data is safe (it is re-created when data arrives again, as
// Slicer's OpenIGTLink connector does, unless AutoCreateNodes is off).
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>

#include "rpPivotCalibration.h"
#include "rpToolPose.h"

class vtkRPScene;
class vtkRPTrackedToolNode;
class vtkRPLinearTransformNode;

class vtkRPTrackingLogic : public vtkObject {
 public:
  static vtkRPTrackingLogic* New();
  vtkTypeMacro(vtkRPTrackingLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene);
  vtkRPScene* GetScene() const { return this->Scene; }

  /// A table of poses written by another thread; node name = slot name (a transform name such
  /// as StylusToTracker). The table must outlive the logic or be removed first. Returns an id.
  int AddPoseSource(const rp::ToolPoseTable* table);
  void RemovePoseSource(int sourceId);

  /// Seconds without a fresh pose before a tool is shown as stale.
  vtkSetMacro(StaleTimeout, double);
  vtkGetMacro(StaleTimeout, double);
  vtkSetMacro(AutoCreateNodes, bool);
  vtkGetMacro(AutoCreateNodes, bool);
  /// When set (e.g. "ReferenceToTracker"), every other tool also gets a <Tool>ToReference node.
  void SetReferenceNodeName(const std::string& name) { this->ReferenceName = name; }

  /// Main thread: copy the newest poses into nodes. `now` in SteadySeconds(). Returns the
  /// number of nodes modified.
  int UpdateNodes(double now);

  struct ToolStatistics {
    std::string NodeName, NodeID;
    int Status = 0;          // vtkRPTrackedToolNode::Status
    uint64_t Received = 0, Dropped = 0;
    double RateHz = 0;       // fresh poses per second (running estimate)
    double LatencySeconds = 0;  // receive → node update, last fresh pose
    double ErrorRMS = -1;
  };
  std::vector<ToolStatistics> GetToolStatistics() const;

  /// StylusTipToStylus as a child transform of the stylus node (created or updated).
  vtkRPLinearTransformNode* ApplyPivotCalibration(const rp::PivotResult& result, const std::string& stylusNodeName,
                                                  const std::string& tipNodeName = "StylusTipToStylus");

 protected:
  vtkRPTrackingLogic();
  ~vtkRPTrackingLogic() override;

 private:
  vtkRPTrackingLogic(const vtkRPTrackingLogic&) = delete;
  void operator=(const vtkRPTrackingLogic&) = delete;

  struct Tool {
    std::string NodeName, NodeID;
    int Status = 0;
    double LastFreshTime = 0, RateHz = 0, Latency = 0, ErrorRMS = -1;
    uint64_t LastReceived = 0;
    rp::ToolPose Pose;
    bool HasPose = false;
  };
  struct Source {
    const rp::ToolPoseTable* Table = nullptr;
    rp::ToolPoseReader Reader;
    std::vector<Tool> Tools;  // by slot
  };
  vtkRPTrackedToolNode* NodeFor(Tool& tool);
  void WriteNode(vtkRPTrackedToolNode* node, const rp::ToolPose& pose, int status, double errorRMS);

  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
  std::map<int, Source> Sources;
  int NextSourceId = 1;
  double StaleTimeout = 0.5;
  bool AutoCreateNodes = true;
  std::string ReferenceName;
  std::map<std::string, std::string> DerivedNodeIDs;
};

#endif
