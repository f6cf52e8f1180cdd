#include "rpToolInput.h"

namespace rp {

bool ToolInput::Read(double time, ToolSample& sample) noexcept {
  if (this->Transform.Read(this->Tick) == 0) this->Tick = DeviceToScene{};
  DeviceState device;
  if (!this->Device.Read(time, device)) return false;
  sample.Buttons = device.Buttons;
  if (this->InScene) {
    sample.StylusToScene = device.StylusToDevice;
    sample.Velocity = device.Velocity;
  } else {
    sample.StylusToScene = this->Tick.StylusInScene(device.StylusToDevice);
    sample.Velocity = this->Tick.DeviceToRAS.Rotate(device.Velocity) * this->WorkspaceScale();
  }
  return true;
}

void ToolInput::WriteForce(const Vec3& force) noexcept {
  this->Device.WriteForce(this->InScene ? force : this->Tick.DeviceToRAS.RotateInverse(force));
}

}  // namespace rp
