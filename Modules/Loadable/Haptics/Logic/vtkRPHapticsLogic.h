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

  /// The simulated device's profile by name ("omni", the default, or "touch"; see
  /// rpDeviceProfiles.h). False (and `error` lists the names) for an unknown one or while
  /// running.
  bool SetDeviceProfile(const std::string& name, std::string& error);
  const std::string& GetDeviceProfile() const { return this->Profile; }
  /// Tissue materials from this file instead of Resources/Materials/materials.json (empty:
  /// that file).
  void SetMaterialsPath(const std::string& path) { this->MaterialsPath = path; }

  /// Starts the 1 kHz loop with the simulated device on the scene's haptic models, materials
  /// from materials.json (rp::LoadMaterialTable). False (and `error` names the problem) when
  /// there is no scene, no haptic model, the material table cannot be read or it already runs.
  /// Tissues clamped to the device's limits are in GetSession()->Warnings().
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
  std::string LogPath, MaterialsPath;
  std::string Profile;
};

#endif
