#include "vtkRPHapticsLogic.h"

#include <chrono>
#include <thread>

#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>

#include "rpDeviceProfiles.h"
#include "rpFixtureConstraint.h"
#include "rpHapticSceneBridge.h"
#include "rpSimulatedDevice.h"
#include "vtkRPPlanningLogic.h"

vtkStandardNewMacro(vtkRPHapticsLogic);

vtkRPHapticsLogic::vtkRPHapticsLogic()
    : Device(std::make_unique<rp::SimulatedDevice>()),
      Profile(rp::DeviceProfiles().front().Key),
      Planning(vtkSmartPointer<vtkRPPlanningLogic>::New()) {}

bool vtkRPHapticsLogic::SetDeviceProfile(const std::string& name, std::string& error) {
  if (this->IsRunning()) {
    error = "haptics: stop the device before changing it";
    return false;
  }
  rp::DeviceProfile profile;
  if (!rp::FindDeviceProfile(name, profile, error)) return false;
  this->Session.reset();  // no session may keep the old device
  this->Device = std::make_unique<rp::SimulatedDevice>(profile.Info);
  this->Profile = profile.Key;
  this->Modified();
  return true;
}

vtkRPHapticsLogic::~vtkRPHapticsLogic() { this->Stop(); }

void vtkRPHapticsLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Running: " << (this->IsRunning() ? "yes" : "no") << "\n";
  os << indent << "DeviceProfile: " << this->Profile << "\n";
  if (this->Session) os << indent << "HapticTriangles: " << this->Session->SceneTriangles() << "\n";
}

bool vtkRPHapticsLogic::SetPlanFixtures(const rp::PlanFixtureChoice& choice, std::string& error) {
  if (this->Scene == nullptr) {
    error = "haptics: no scene";
    return false;
  }
  this->Planning->SetScene(this->Scene);
  std::shared_ptr<const rp::FixtureSet> set = this->Planning->MakePlanFixtures(choice, error);
  if (!set) return false;  // refused: the set in use stays
  this->PlanFixtures = set;
  rp::InstallFixtures(this->PlanFixtures, this->Settings.MakeConstraints, this->IsRunning() ? &this->Session->Servo().Constraints() : nullptr);
  return true;
}

void vtkRPHapticsLogic::SetSimulatedTrajectory(std::shared_ptr<const rp::Trajectory> path) { this->Path = std::move(path); }

std::unique_ptr<rp::HapticScene> vtkRPHapticsLogic::PreviewHapticScene(std::string& error) {
  rp::MaterialTable table;
  if (!rp::LoadMaterialTable(table, error, this->MaterialsPath)) return nullptr;
  std::vector<std::string> warnings;
  return rp::HapticScene::Build(rp::CollectHapticMeshes(this->Scene, warnings), table, warnings, error);
}

bool vtkRPHapticsLogic::StartSimulated(std::string& error) {
  if (this->Scene == nullptr) {
    error = "haptics: no scene";
    return false;
  }
  if (this->IsRunning()) {
    error = "haptics: already running";
    return false;
  }
  this->Session.reset();
  rp::HapticSession::Options options = this->Settings;
  options.PosesInScene = true;  // the stylus is set in RAS (viewer, followed tool, script)
  if (!rp::LoadMaterialTable(options.Materials, error, this->MaterialsPath)) return false;
  this->Device->SetTrajectory(this->Path);  // the loop is stopped
  this->Session = std::make_unique<rp::HapticSession>(*this->Device);
  if (!this->Session->Start(this->Scene, options, error)) {
    this->Session.reset();
    return false;
  }
  if (this->Session->SceneTriangles() == 0) {
    this->Stop();
    this->Session.reset();
    error = "haptics: the scene has no haptic models (model nodes with Haptic on and polygons)";
    return false;
  }
  return true;
}

bool vtkRPHapticsLogic::RunSimulated(double seconds, const std::function<void(double)>& onFrame, std::string& error) {
  if (!this->StartSimulated(error)) return false;
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(33));  // display rate
    this->Update();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (onFrame) onFrame(elapsed);
    if (elapsed >= seconds) break;
  }
  this->Stop();
  return true;
}

void vtkRPHapticsLogic::Stop() {
  if (this->Session) this->Session->Stop();
}

bool vtkRPHapticsLogic::IsRunning() const { return this->Session && this->Session->Running(); }

void vtkRPHapticsLogic::SetSimulatedStylusPose(vtkMatrix4x4* m) {
  if (m != nullptr) this->Device->SetManualPose(rp::PoseFromMatrix(m));
}

bool vtkRPHapticsLogic::Update() {
  if (!this->IsRunning()) return false;
  rp::Pose followed;
  if (!this->FollowedID.empty() && rp::ReadToolPose(this->Scene, this->FollowedID, followed))
    this->Device->SetManualPose(followed);  // the tracked tool's tip, in RAS as the servo takes it
  return this->Session->Update();
}

void vtkRPHapticsLogic::GetLastForce(double force[3]) const {
  const rp::Vec3 f = this->Device->LastForce();
  force[0] = f.x;
  force[1] = f.y;
  force[2] = f.z;
}
