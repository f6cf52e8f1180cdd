#ifndef vtkRPHapticsLogic_h
#define vtkRPHapticsLogic_h
// The Haptics module's logic (what Module::Logic() returns), the one way to touch the scene
// whoever asks: the panel, `roboplan haptics` and the demo call these functions. It runs a haptic
// session (rpHapticSession) on the scene's haptic models with the simulated device, whose stylus
// is in RAS as the servo takes it (rpToolInput): moved by the viewer (mouse, spin boxes),
// following a tracked tool's tip node (a stylus or drill under the tracker drives the proxy), or
// scripted along a path in RAS. Main thread only; call Update() from a display-rate timer, or
// RunSimulated() to run a scripted session to its end.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpHapticSession.h"
#include "rpPlanFixtures.h"

class vtkMatrix4x4;
class vtkRPPlanningLogic;
class vtkRPScene;

namespace rp {
class SimulatedDevice;
class Trajectory;
}  // namespace rp

class vtkRPHapticsLogic : public vtkObject {
 public:
  static vtkRPHapticsLogic* New();
  vtkTypeMacro(vtkRPHapticsLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// The simulated device's profile by name ("omni", the default, or "touch"; see
  /// rpDeviceProfiles.h). False (and `error` lists the names) for an unknown one or while
  /// running.
  bool SetDeviceProfile(const std::string& name, std::string& error);
  const std::string& GetDeviceProfile() const { return this->Profile; }
  /// Tissue materials from this file instead of Resources/Materials/materials.json (empty:
  /// that file).
  void SetMaterialsPath(const std::string& path) { this->MaterialsPath = path; }

  // ---- the session's settings (before StartSimulated / RunSimulated)
  /// Tool points in the stylus frame (mm), [0] the tip; default the tip alone.
  void SetToolPoints(const std::vector<rp::Vec3>& points) { this->Settings.ToolPoints = points; }
  /// The force ramp after start (s).
  void SetRampSeconds(double seconds) { this->Settings.RampSeconds = seconds; }
  /// The servo loop (rate, spin, CPU pinning and shield, priority).
  void SetLoopOptions(const rp::ServoLoop::Options& options) { this->Settings.Loop = options; }
  /// Gather the run's force figures (HapticSession::Summary()) from every tick.
  void SetSummarize(bool summarize) { this->Settings.Summarize = summarize; }
  /// The virtual fixtures of each session (rpToolConstraint.h: made anew for each, a set belongs to
  /// its servo once handed over); nullptr: none. A running session: GetSession()->Servo().Constraints().
  void SetConstraints(std::function<std::unique_ptr<rp::ToolConstraints>()> make) {
    this->Settings.MakeConstraints = std::move(make);
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
  /// The session log CSV written while running (empty: none); flushed by Stop().
  void SetLogPath(const std::string& path) { this->Settings.LogPath = path; }
  const std::string& GetLogPath() const { return this->Settings.LogPath; }
  /// Scripted motion of the simulated stylus, in RAS (nullptr: the viewer or a followed tool moves it).
  void SetSimulatedTrajectory(std::shared_ptr<const rp::Trajectory> path);
  /// The scene's haptic models as the next session will touch them (to plan a scripted path
  /// over them). nullptr and `error` when they cannot be built; an empty tree when there are none.
  std::unique_ptr<rp::HapticScene> PreviewHapticScene(std::string& error);

  // ---- running
  /// Starts the 1 kHz loop with the simulated device on the scene's haptic models, materials
  /// from materials.json (rp::LoadMaterialTable). False (and `error` names the problem) when
  /// there is no scene, no haptic model, the material table cannot be read or it already runs.
  /// Tissues clamped to the device's limits are in GetSession()->Warnings().
  bool StartSimulated(std::string& error);
  /// Starts, updates at display rate for `seconds` (calling `onFrame(elapsed seconds)` after each
  /// update: progress, new warnings) and stops. The finished session stays in GetSession().
  bool RunSimulated(double seconds, const std::function<void(double)>& onFrame, std::string& error);
  void Stop();
  bool IsRunning() const;
  /// The simulated stylus pose in RAS (4x4, mm), e.g. from the mouse or the panel's spin boxes;
  /// the servo takes it as it is (HapticDeviceToRAS only gives the workspace scale).
  void SetSimulatedStylusPose(vtkMatrix4x4* stylusToRAS);
  /// Follows this transformable node's pose instead (a tracked stylus's or drill's tip node, in
  /// RAS: it drives the haptic proxy); "" stops. Read at display rate by Update().
  void SetFollowedNodeID(const std::string& id) { this->FollowedID = id; }
  const std::string& GetFollowedNodeID() const { return this->FollowedID; }
  /// Display-rate update: rebuilds the haptic scene when models changed and copies the HIP,
  /// proxy and force into the HapticInterfacePoint / HapticProxy tool nodes.
  bool Update();
  /// The last force sent to the device (N, RAS: the simulated stylus is in the scene's frame).
  void GetLastForce(double force[3]) const;
  /// The running session (servo state, timing, tissue names), or the last one after Stop()
  /// (its figures) until the next starts; nullptr before any.
  rp::HapticSession* GetSession() const { return this->Session.get(); }

 protected:
  vtkRPHapticsLogic();
  ~vtkRPHapticsLogic() override;

 private:
  vtkRPHapticsLogic(const vtkRPHapticsLogic&) = delete;
  void operator=(const vtkRPHapticsLogic&) = delete;
  vtkRPScene* Scene = nullptr;  // not owned (the host's scene outlives its modules)
  rp::HapticSession::Options Settings;
  std::shared_ptr<const rp::Trajectory> Path;
  std::unique_ptr<rp::SimulatedDevice> Device;
  std::unique_ptr<rp::HapticSession> Session;  // after Device: destroyed first
  std::string MaterialsPath, FollowedID;
  std::string Profile;
  vtkSmartPointer<vtkRPPlanningLogic> Planning;  // the plan's snapshot (its structures' surfaces cached)
  std::shared_ptr<const rp::FixtureSet> PlanFixtures;
};

#endif
