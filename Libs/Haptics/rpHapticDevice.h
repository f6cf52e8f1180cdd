#pragma once
// What the haptic servo loop needs from a device (simulated, OpenHaptics, ...): a 6-DoF pose in
// the device frame (mm), velocity, buttons, a 3-DoF force out (N), and the limits the renderer
// must respect. Read/WriteForce are called on the servo thread and must not allocate or block.
#include <cstdint>
#include <string>

#include "rpVec3.h"

namespace rp {

/// A rotation (row-major 3x3) and translation.
struct Pose {
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 T;
  Vec3 Apply(const Vec3& p) const noexcept { return this->Rotate(p) + this->T; }
  Vec3 Rotate(const Vec3& v) const noexcept {
    return {R[0] * v.x + R[1] * v.y + R[2] * v.z, R[3] * v.x + R[4] * v.y + R[5] * v.z,
            R[6] * v.x + R[7] * v.y + R[8] * v.z};
  }
  Vec3 RotateInverse(const Vec3& v) const noexcept {
    return {R[0] * v.x + R[3] * v.y + R[6] * v.z, R[1] * v.x + R[4] * v.y + R[7] * v.z,
            R[2] * v.x + R[5] * v.y + R[8] * v.z};
  }
};

struct DeviceState {
  Pose StylusToDevice;  // tip position (mm) and stylus orientation in the device frame
  Vec3 Velocity;        // mm/s, device frame
  uint32_t Buttons = 0;
};

/// A device's limits. The defaults are a generic device for unit tests, not any model: the
/// simulated device takes a profile (rpDeviceProfiles.h), real devices report their own.
struct DeviceInfo {
  std::string Name;
  Vec3 WorkspaceMin{-80, -60, -35}, WorkspaceMax{80, 60, 35};  // mm, device frame
  double MaxForce = 3.3;                // N (eq. 6 threshold)
  double NominalMaxStiffness = 2.5;     // N/mm
  double NominalMaxDamping = 0.002;     // N·s/mm
  double PhysicalDamping = 0.003;       // N·s/mm, the device's own (Colgate-Schenkel "b"); 0: unknown
  /// How fast the force may change on an event rather than a motion (a virtual fixture switched on
  /// or off, captured or released, a new plan): N/s, so one tick's step is MaxForceRate × period.
  /// The default is what the stiffest spring the device renders does when the hand moves at
  /// 0.5 m/s (NominalMaxStiffness × 500 mm/s): an event never jolts harder than touching does.
  double MaxForceRate = 2.5 * 500;
  /// Largest torque (N·mm) the device renders; 0 for 3-DoF force output (Omni, Touch).
  double MaxTorque = 0;
};

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  virtual bool Open(std::string& error) = 0;
  virtual void Close() = 0;
  virtual const DeviceInfo& Info() const = 0;
  /// Servo thread. `time` is the servo's scheduled time (s). False on a device error (the
  /// watchdog then zeroes the force).
  virtual bool Read(double time, DeviceState& state) noexcept = 0;
  /// Servo thread. Force in N, device frame.
  virtual void WriteForce(const Vec3& force) noexcept = 0;
  /// Servo thread. Torque in N·mm, device frame; only devices with DeviceInfo::MaxTorque > 0 are
  /// sent one (the default drops it).
  virtual void WriteTorque(const Vec3& torque) noexcept { (void)torque; }
};

}  // namespace rp
