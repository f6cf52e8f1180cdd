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
// Navigation.Guidance ("entryErrorMm=…;angleDeg=…;…") and GetLastReadout(). Main thread only.
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpGuidanceReadout.h"

class vtkRPScene;
class vtkRPModelNode;
class vtkRPTransformableNode;
class vtkStaticCellLocator;
class vtkCallbackCommand;

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
  const rp::GuidanceReadout& GetLastReadout() const { return this->LastReadout; }
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

  vtkRPScene* Scene = nullptr;  // not owned
  std::string ToolNodeID;
  std::vector<std::string> TargetModelNodeIDs;
  std::string TrajectoryNodeID;
  rp::GuidanceReadout LastReadout;
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
