#ifndef vtkRPNavigationLogic_h
#define vtkRPNavigationLogic_h
// Navigation (seed sections 3.3 and 4): follows a tool tip (a transform node whose origin is the
// tip, e.g. StylusTipToStylus under StylusToTracker under TrackerToRAS, or the haptic proxy),
// measures the distance from the tip to the nearest surface of chosen models, and flags it when
// it falls under a warning distance. Results go onto the tool node as attributes
// (Navigation.DistanceMM, Navigation.ClosestModel, Navigation.ClosestPointRAS,
// Navigation.Warning) so the viewer shows them without knowing this module. With a planned
// trajectory chosen (SetTrajectoryNodeID, issue 38) it also gives the tool's read-out against the
// plan (rpGuidanceReadout.h: entry error, angle, depth to target, lateral distance) as
// Navigation.Guidance ("entryErrorMm=…;angleDeg=…;…") and GetLastReadout(), measured against the
// scene's structures at risk as the Planning logic finds them (protected models and segments, with
// their margins), and hands the same read-out to OpenIGTLink (GetReadoutOutbox: a TRANSFORM
// ToolTipToTrajectory and a STRING GuidanceReadout, sent by an rp::IgtlServer the moment they are
// published; StartReadoutServer serves them). Main thread only.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpGuidanceReadout.h"
#include "rpPlanSnapshot.h"
#include "rpScoredExecution.h"

class vtkRPScene;
class vtkRPModelNode;
class vtkRPTransformableNode;
class vtkStaticCellLocator;
class vtkCallbackCommand;
class vtkRPPlanningLogic;
namespace rp {
class IgtlOutbox;
class IgtlServer;
class ToolPoseTable;
}  // namespace rp

class vtkRPNavigationLogic : public vtkObject {
 public:
  static vtkRPNavigationLogic* New();
  vtkTypeMacro(vtkRPNavigationLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene);
  vtkRPScene* GetScene() const { return this->Scene; }

  /// The tool whose origin is the tip. Observed: the logic updates when it moves.
  void SetToolNodeID(const std::string& id);
  const std::string& GetToolNodeID() const { return this->ToolNodeID; }
  /// Models the distance is measured to (e.g. bone, a ligament).
  void SetTargetModelNodeIDs(const std::vector<std::string>& ids);
  /// The planned trajectory (a vtkRPTrajectoryNode) the tool is read out against ("" none). The
  /// tool points along its −z (the stylus's and the haptic proxy's convention).
  void SetTrajectoryNodeID(const std::string& id);
  const std::string& GetTrajectoryNodeID() const { return this->TrajectoryNodeID; }
  /// The last read-out against the trajectory (Valid false without a tool or a complete trajectory).
  /// Its closest structure is the closest of the scene's structures at risk to the tool's surface
  /// (the trajectory's tool radius around the tip), WithinMargin under that structure's margin.
  const rp::GuidanceReadout& GetLastReadout() const { return this->LastReadout; }
  /// Why the last read-out has no structure although the scene has some (e.g. an empty segment).
  const std::string& GetStructuresProblem() const { return this->StructuresProblem; }

  /// Every read-out goes here as it is computed (TRANSFORM rp::ReadoutTransformName, STRING
  /// rp::ReadoutStringName); any rp::IgtlServer given it (Options::Outbox) sends them at once.
  const rp::IgtlOutbox& GetReadoutOutbox() const { return *this->Outbox; }
  /// Serves the read-outs over OpenIGTLink (the Tracking module's server, as `roboplan track
  /// --serve`: Slicer's OpenIGTLinkIF connects as a client). Port 0: an ephemeral one. False with
  /// the reason; a running server is replaced.
  bool StartReadoutServer(int port, std::string& error, const std::string& bindAddress = "127.0.0.1");
  void StopReadoutServer();
  /// The port served (0: none) and the clients connected.
  int GetReadoutServerPort() const;
  int GetReadoutClientCount() const;
  /// Scores an execution against a trajectory of the scene (issue 38; `roboplan score` and the
  /// panel): the path file read (a drilling recording, a PLUS sequence through a transform, a CSV
  /// R,A,S), scored against the trajectory (rpExecutionScore.h), the bone model's surface for the
  /// breach, the scene's structures at risk for the clearance. False with `error`; the scene is
  /// not changed either way.
  bool ScoreExecution(const rp::ScoreRequest& request, rp::ScoredExecution& result, std::string& error);
  /// Its first half, on the main thread: the scene's plan and the bone's surface taken into `job`,
  /// so that rp::RunScore(job) may run on another thread (the panel keeps its window live).
  bool PrepareScore(const rp::ScoreRequest& request, rp::ScoredExecution& job, std::string& error);

  vtkSetMacro(WarningDistance, double);
  vtkGetMacro(WarningDistance, double);

  struct Result {
    bool Valid = false;            // a tool and at least one non-empty model
    double TipRAS[3] = {0, 0, 0};
    double DistanceMM = 0;         // signed: negative inside the closest model
    double ClosestPointRAS[3] = {0, 0, 0};
    std::string ClosestModelID;
    bool Warning = false;          // |distance| under the warning distance (or inside)
  };
  /// Recomputes now (also called automatically when the tool moves).
  Result Update();
  const Result& GetLastResult() const { return this->Last; }

  /// Tip position of any transformable node (origin of its frame in world RAS).
  static void GetTipRAS(vtkRPTransformableNode* tool, double tipRAS[3]);

 protected:
  vtkRPNavigationLogic();
  ~vtkRPNavigationLogic() override;

 private:
  vtkRPNavigationLogic(const vtkRPNavigationLogic&) = delete;
  void operator=(const vtkRPNavigationLogic&) = delete;
  static void OnToolMoved(vtkObject*, unsigned long, void* clientData, void*);
  void ObserveTool();
  vtkStaticCellLocator* LocatorFor(vtkRPModelNode* model);
  void UpdateReadout(vtkRPTransformableNode* tool);
  std::vector<rp::ReadoutStructure> CurrentStructures();
  void PublishReadout();

  vtkRPScene* Scene = nullptr;  // not owned
  std::string ToolNodeID;
  std::vector<std::string> TargetModelNodeIDs;
  std::string TrajectoryNodeID;
  rp::GuidanceReadout LastReadout;
  std::string StructuresProblem;
  vtkSmartPointer<vtkRPPlanningLogic> Planning;  // finds the structures at risk (cached surfaces)
  std::vector<rp::StructureAtRiskSnapshot> Structures;
  std::unique_ptr<rp::IgtlOutbox> Outbox;
  std::unique_ptr<rp::ToolPoseTable> NoPoses;  // the read-out server streams no tool of its own
  std::unique_ptr<rp::IgtlServer> Server;
  double WarningDistance = 3.0;
  Result Last;
  vtkSmartPointer<vtkCallbackCommand> ToolCallback;
  vtkObject* ObservedTool = nullptr;
  unsigned long ToolObserverTag = 0;
  struct CachedLocator {
    vtkSmartPointer<vtkStaticCellLocator> Locator;
    vtkMTimeType PolyDataTime = 0;
  };
  std::map<std::string, CachedLocator> Locators;
  bool Updating = false;
};

#endif
