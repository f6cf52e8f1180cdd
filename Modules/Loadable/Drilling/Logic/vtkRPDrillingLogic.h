#ifndef vtkRPDrillingLogic_h
#define vtkRPDrillingLogic_h
// The Drilling module's logic (what Module::Logic() returns; main thread only), the one way to
// drill whoever asks: the panel, `roboplan drill` and the demo call these functions.
//  - The bone: built from a segmentation node's segments (cortical/trabecular from a CT volume
//    node when one is chosen), from a source the caller assembled (the command's files, the
//    demo's labels), or an analytic block; kept across sessions with its display (the re-contoured
//    mesh), shown as a model node "<segment> (drilled)".
//  - A session (rpDrillSession) with the simulated device: moved by the panel, following a
//    tracked tool (its pose in RAS, as the servo takes it) or scripted along a path in RAS.
//    StartSimulated() runs it in real time for the viewer (Update() from a display-rate timer swaps
//    the re-contoured mesh into the model node and moves the HapticInterfacePoint / HapticProxy
//    tool nodes); RunSimulated() runs a stroke to its end, scripted or in real time.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpDrillBoneBuilder.h"
#include "rpDrillSession.h"
#include "rpPlanFixtures.h"
#include "rpSimulatedHand.h"

class vtkPolyData;
class vtkRPPlanningLogic;
class vtkRPScene;

namespace rp {
class SimulatedDevice;
class Trajectory;
}  // namespace rp

class vtkRPDrillingLogic : public vtkObject {
 public:
  static vtkRPDrillingLogic* New();
  vtkTypeMacro(vtkRPDrillingLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }
  /// Tissue materials from this file instead of Resources/Materials/materials.json ("": that file).
  void SetMaterialsPath(const std::string& path) { this->MaterialsPath = path; }

  // ---- the bone
  struct BoneChoice {
    std::string SegmentationID;                  // a vtkRPSegmentationNode in the scene
    std::vector<std::string> BoneSegments;       // segments to drill: ID, name or label value
    std::vector<std::string> ProtectedSegments;  // segments the burr must not reach
    std::string CTVolumeID;                      // optional vtkRPScalarVolumeNode (HU → cortical/trabecular)
    double VoxelMm = 0.3;
  };
  /// Builds the voxel bone and its model node from scene nodes (stops a running session). False
  /// names the problem.
  bool BuildBone(const BoneChoice& choice, std::string& error);
  /// The same from a source the caller assembled (labels, segments, CT, region, the bone's own
  /// surface); `boneNames` name the model node.
  bool BuildBone(const rp::DrillBoneSource& source, const std::vector<std::string>& boneNames, std::string& error,
                 const rp::ProgressCallback& progress = nullptr);
  /// An analytic block of bone between `lo` and `hi` (RAS mm): all cortical, or a cortical shell
  /// `shellMm` thick around a trabecular core.
  bool BuildBlockBone(const rp::Vec3& lo, const rp::Vec3& hi, double shellMm, double voxelMm, std::string& error);
  bool HasBone() const { return static_cast<bool>(this->Bone); }
  rp::DrillVolume* GetBone() const { return this->Bone.get(); }
  const rp::DrillBoneReport& GetBoneReport() const { return this->Report; }
  /// The drillable materials (index = DrillState material index) and their tissue names.
  const std::vector<rp::Material>& GetMaterials() const { return this->Materials; }
  std::vector<std::string> GetTissueNames() const;
  /// The protected structures' surface (empty when none).
  const rp::TriangleMesh& GetProtectedSurface() const { return this->ProtectedSurface; }
  const std::string& GetDrilledModelID() const { return this->ModelID; }
  /// The drilled bone's mesh as shown (the model node's).
  vtkPolyData* GetDrilledMesh() const;

  // ---- the session's settings (before StartSimulated / RunSimulated)
  void SetServoOptions(const rp::DrillServoOptions& options) { this->ServoSettings = options; }
  const rp::DrillServoOptions& GetServoOptions() const { return this->ServoSettings; }
  /// Real-time loop settings (priority, CPU pinning).
  void SetLoopOptions(const rp::ServoLoop::Options& options) { this->LoopSettings = options; }
  /// Scripted motion of the simulated burr, in RAS (nullptr: the panel or a followed tool moves it).
  void SetSimulatedTrajectory(std::shared_ptr<const rp::Trajectory> path);
  /// A hand holding the drill on that script: it means to follow the trajectory, with tremor and
  /// drift, and the force pushes it (rpSimulatedHand.h; a fresh one for every session, so runs
  /// with the same seed are the same hand). ClearSimulatedHand: the burr follows the script exactly.
  void SetSimulatedHand(const rp::HandNoise& noise, const rp::HandImpedance& impedance);
  void ClearSimulatedHand() { this->HasHand = false; }
  /// Whether the scene's other haptic models are touched in the same tick (default on: in the
  /// viewer the burr meets the soft tissue on its way; a planned stroke through it turns this off).
  void SetTouchOtherModels(bool touch) { this->TouchOthers = touch; }
  /// The virtual fixtures of each session (rpToolConstraint.h: made anew for each, a set belongs to
  /// its servo once handed over); nullptr: none. A running session: GetSession()->Servo().Constraints().
  void SetConstraints(std::function<std::unique_ptr<rp::ToolConstraints>()> make) {
    this->MakeConstraints = std::move(make);
    this->PlanFixtures.reset();
  }
  /// The plan's virtual fixtures (issue 38; what the panel's Guidance group and tests call): builds
  /// the fixtures `choice` switches on from the scene's plan (vtkRPPlanningLogic::MakePlanFixtures),
  /// installs them for every next session and hands them to a running one, where a fixture
  /// switched on or off fades in or out (no force step beyond the device's event rate). A choice
  /// with none clears them. False with `error` naming the problem; the fixtures in use are kept.
  bool SetPlanFixtures(const rp::PlanFixtureChoice& choice, std::string& error);
  /// The plan's fixtures in use (null: none set through SetPlanFixtures since the last SetConstraints).
  std::shared_ptr<const rp::FixtureSet> GetPlanFixtures() const { return this->PlanFixtures; }
  /// The next run starts with the burr placed at `center` (RAS), cutting when `control` has it on
  /// (a stroke that begins inside bone: `roboplan drill --from`).
  void PlaceBurr(const rp::Vec3& center, const rp::DrillControl& control);
  /// The drill path recording written while drilling ("" none).
  void SetRecordPath(const std::string& path) { this->RecordPath = path; }
  const std::string& GetRecordPath() const { return this->RecordPath; }

  // ---- drilling
  /// Starts drilling in real time with the simulated device (its pose from SetSimulatedBurrPosition,
  /// a followed tool or the trajectory). False names the problem (no bone, already running, ...).
  bool StartSimulated(std::string& error);
  /// Runs a stroke to its end with the simulated device (scripted, or real time with run.Realtime),
  /// the mesh swapped into the model node as it comes, every record kept in `result`.
  bool RunSimulated(const rp::DrillRunOptions& run, rp::DrillRunResult& result, std::string& error);
  void Stop();
  bool IsRunning() const;
  void SetBurrOn(bool on);
  void SetBurrRadius(double mm);
  void SetRpm(double rpm);
  const rp::DrillControl& GetControl() const { return this->Control; }
  /// Undo the last stroke / restore the bone as built (while running; done by the servo thread).
  void Undo();
  void ResetBone();
  /// Moves the simulated burr to a RAS point (the servo takes it in RAS, as it is).
  void SetSimulatedBurrPosition(const double ras[3]);
  /// Follows this transformable node's pose (e.g. a tracked drill's tip node: its origin is the
  /// burr's centre, its axes the drill's) instead, in RAS; "" stops.
  void SetFollowedNodeID(const std::string& id) { this->FollowedID = id; }

  /// Display-rate update (main thread). True when the drilled model changed.
  bool Update();
  bool ReadState(rp::DrillState& state) const;
  /// The running session, or the last one (stopped) until the next starts.
  rp::DrillSession* GetSession() const { return this->Session.get(); }
  /// A picture of the tunnel along the path drilled so far.
  bool SaveTunnelPicture(const std::string& path, std::string& error);

 protected:
  vtkRPDrillingLogic();
  ~vtkRPDrillingLogic() override;

 private:
  vtkRPDrillingLogic(const vtkRPDrillingLogic&) = delete;
  void operator=(const vtkRPDrillingLogic&) = delete;
  bool LoadMaterials(std::string& error);
  bool ShowBone(const std::vector<std::string>& boneNames);
  bool PrepareSession(bool keepRecords, std::string& error);
  bool SwapMesh(vtkPolyData* mesh);

  vtkRPScene* Scene = nullptr;  // not owned
  std::string MaterialsPath;
  rp::MaterialTable Table;
  std::unique_ptr<rp::DrillVolume> Bone;
  std::unique_ptr<rp::DrillDisplay> Display;  // the bone's mesh, kept across sessions
  rp::TriangleMesh ProtectedSurface;
  std::vector<rp::Material> Materials;
  rp::DrillBoneReport Report;
  std::vector<std::string> BoneNames;  // segment names (their haptic models are left to the burr)
  std::string ModelID, FollowedID, RecordPath;
  rp::DrillControl Control;
  rp::DrillServoOptions ServoSettings;
  rp::ServoLoop::Options LoopSettings;
  std::function<std::unique_ptr<rp::ToolConstraints>()> MakeConstraints;
  vtkSmartPointer<vtkRPPlanningLogic> Planning;  // the plan's snapshot (its structures' surfaces cached)
  std::shared_ptr<const rp::FixtureSet> PlanFixtures;
  bool TouchOthers = true;
  bool HasHand = false;
  rp::HandNoise HandTremor;
  rp::HandImpedance HandGrip;
  bool Placed = false;
  rp::Vec3 PlacedAt;
  rp::DrillControl PlacedControl;
  std::unique_ptr<rp::SimulatedDevice> Device;
  std::unique_ptr<rp::DrillSession> Session;  // after Bone, Display and Device: destroyed first
};

#endif
