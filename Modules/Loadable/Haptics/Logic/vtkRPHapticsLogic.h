#ifndef vtkRPHapticsLogic_h
#define vtkRPHapticsLogic_h
// The Haptics module's logic (what Module::Logic() returns): runs a haptic session on the scene
// with the simulated device driven interactively (e.g. by the viewer's mouse), so the module is
// usable without hardware. Main thread only; call Update() from a display-rate timer.
#include <memory>
#include <string>

#include <vtkObject.h>

class vtkMatrix4x4;
class vtkRPScene;

namespace rp {
class HapticSession;
class SimulatedDevice;
}  // namespace rp

class vtkRPHapticsLogic : public vtkObject {
 public:
  static vtkRPHapticsLogic* New();
  vtkTypeMacro(vtkRPHapticsLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// Starts the 1 kHz loop with the simulated device on the scene's haptic models. False (and
  /// `error` names the problem) when there is no scene, no haptic model or it already runs.
  bool StartSimulated(std::string& error);
  void Stop();
  bool IsRunning() const;
  /// The simulated stylus pose in the device frame (4x4, mm), e.g. from the mouse.
  void SetSimulatedStylusPose(vtkMatrix4x4* stylusToDevice);
  /// Display-rate update: rebuilds the haptic scene when models changed and copies the HIP,
  /// proxy and force into the HapticInterfacePoint / HapticProxy tool nodes.
  bool Update();
  /// The last force sent to the device (N, device frame).
  void GetLastForce(double force[3]) const;
  /// The running session (servo state, timing, tissue names), or nullptr when stopped.
  rp::HapticSession* GetSession() const { return this->Session.get(); }
  /// The session log CSV written while running (empty: none); flushed by Stop().
  void SetLogPath(const std::string& path) { this->LogPath = path; }
  const std::string& GetLogPath() const { return this->LogPath; }

 protected:
  vtkRPHapticsLogic();
  ~vtkRPHapticsLogic() override;

 private:
  vtkRPHapticsLogic(const vtkRPHapticsLogic&) = delete;
  void operator=(const vtkRPHapticsLogic&) = delete;
  vtkRPScene* Scene = nullptr;  // not owned (the host's scene outlives its modules)
  std::unique_ptr<rp::SimulatedDevice> Device;
  std::unique_ptr<rp::HapticSession> Session;
  std::string LogPath;
};

#endif
