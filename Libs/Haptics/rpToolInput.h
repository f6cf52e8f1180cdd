#pragma once
// The tool a servo follows, as every servo sees it (haptics and drilling): its pose in the scene
// (RAS, mm) and the force back to the hand (N, RAS). A pose is converted once, here, where the
// device's samples enter the servo:
//   - a haptic device moving in its own frame (the OpenHaptics device, a SimulatedDevice scripted
//     in device coordinates) crosses HapticDeviceToRAS (rotation, translation and the workspace
//     scale); its force goes back through the rotation;
//   - a pose that is in the scene already (a SimulatedDevice moved by the viewer's spin boxes or
//     mouse, following a tracked tool's tip node, or scripted along a path in RAS) is taken as it
//     is (SetPosesInScene): only the workspace scale of the device it stands for is kept, for the
//     gain limits (Colgate-Schenkel scales K by it).
// So a tracked stylus or drill drives the haptic proxy or the burr without going to device
// coordinates and back. The owner publishes the transform at display rate (any time); the servo
// reads it once per tick in Read(), and WriteForce() / WorkspaceScale() use that tick's copy.
#include "rpHapticDevice.h"
#include "rpLatestValue.h"

namespace rp {

/// Device frame → scene (RAS): scene = R·(Scale·device) + T.
struct DeviceToScene {
  Pose DeviceToRAS;
  double Scale = 1.0;
  /// The stylus pose in the scene (rotations composed; the position scaled, then moved).
  Pose StylusInScene(const Pose& stylusToDevice) const noexcept {
    Pose stylus;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        stylus.R[3 * r + c] = DeviceToRAS.R[3 * r] * stylusToDevice.R[c] + DeviceToRAS.R[3 * r + 1] * stylusToDevice.R[3 + c] +
                              DeviceToRAS.R[3 * r + 2] * stylusToDevice.R[6 + c];
    stylus.T = DeviceToRAS.Apply(stylusToDevice.T * (Scale > 0 ? Scale : 1.0));
    return stylus;
  }
};

/// One sample of the tool, in the scene frame.
struct ToolSample {
  Pose StylusToScene;  // tip position (mm) and stylus orientation in RAS
  Vec3 Velocity;       // mm/s, RAS
  uint32_t Buttons = 0;
};

class ToolInput {
 public:
  explicit ToolInput(HapticDevice& device) : Device(device) {}

  HapticDevice& GetDevice() const { return this->Device; }
  const DeviceInfo& Info() const { return this->Device.Info(); }

  // ---- owner thread
  /// HapticDeviceToRAS (rpHapticSceneBridge's ReadDeviceToScene), any time.
  void SetDeviceToScene(const DeviceToScene& transform) { this->Transform.Publish(transform); }
  /// Whether the device's poses are in the scene frame already (set while the servo is stopped).
  void SetPosesInScene(bool inScene) { this->InScene = inScene; }
  bool PosesInScene() const { return this->InScene; }

  // ---- servo thread (never allocate, lock or log)
  /// This tick's sample in the scene frame; false on a device error (the watchdog zeroes the force).
  bool Read(double time, ToolSample& sample) noexcept;
  /// Force on the hand (N, scene frame), sent in the device's frame.
  void WriteForce(const Vec3& force) noexcept;
  /// Scene mm per device mm this tick (the gain limits).
  double WorkspaceScale() const noexcept { return this->Tick.Scale > 0 ? this->Tick.Scale : 1.0; }

 private:
  HapticDevice& Device;
  LatestValue<DeviceToScene> Transform;
  bool InScene = false;
  DeviceToScene Tick;  // servo thread: the transform read by this tick's Read()
};

}  // namespace rp
