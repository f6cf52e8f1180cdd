#include "vtkRPHapticsLogic.h"

#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>

#include "rpDeviceProfiles.h"
#include "rpHapticSession.h"
#include "rpSimulatedDevice.h"

vtkStandardNewMacro(vtkRPHapticsLogic);

vtkRPHapticsLogic::vtkRPHapticsLogic()
    : Device(std::make_unique<rp::SimulatedDevice>()), Profile(rp::DeviceProfiles().front().Key) {}

bool vtkRPHapticsLogic::SetDeviceProfile(const std::string& name, std::string& error) {
  if (this->IsRunning()) {
    error = "haptics: stop the device before changing it";
    return false;
  }
  rp::DeviceProfile profile;
  if (!rp::FindDeviceProfile(name, profile, error)) return false;
  this->Stop();  // no session may keep the old device
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

bool vtkRPHapticsLogic::StartSimulated(std::string& error) {
  if (this->Scene == nullptr) {
    error = "haptics: no scene";
    return false;
  }
  if (this->IsRunning()) {
    error = "haptics: already running";
    return false;
  }
  this->Session = std::make_unique<rp::HapticSession>(*this->Device);
  rp::HapticSession::Options options;
  options.LogPath = this->LogPath;
  if (!rp::LoadMaterialTable(options.Materials, error, this->MaterialsPath)) {
    this->Session.reset();
    return false;
  }
  if (!this->Session->Start(this->Scene, options, error)) {
    this->Session.reset();
    return false;
  }
  if (this->Session->SceneTriangles() == 0) {
    this->Stop();
    error = "haptics: the scene has no haptic models (model nodes with Haptic on and polygons)";
    return false;
  }
  return true;
}

void vtkRPHapticsLogic::Stop() {
  if (this->Session) this->Session->Stop();
  this->Session.reset();
}

bool vtkRPHapticsLogic::IsRunning() const { return this->Session && this->Session->Running(); }

void vtkRPHapticsLogic::SetSimulatedStylusPose(vtkMatrix4x4* m) {
  if (m == nullptr) return;
  rp::Pose pose;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.R[3 * r + c] = m->GetElement(r, c);
    pose.T[r] = m->GetElement(r, 3);
  }
  this->Device->SetManualPose(pose);
}

bool vtkRPHapticsLogic::Update() { return this->Session ? this->Session->Update() : false; }

void vtkRPHapticsLogic::GetLastForce(double force[3]) const {
  const rp::Vec3 f = this->Device->LastForce();
  force[0] = f.x;
  force[1] = f.y;
  force[2] = f.z;
}
