#pragma once
// Phantom Omni / Touch through the OpenHaptics HD API (compiled only when the SDK is found:
// ROBOPLAN_HAVE_OPENHAPTICS). Units are those of the HD API: mm, mm/s, N. The HD servo
// scheduler drives the 1 kHz loop itself, so this backend runs a ServoTask from the scheduler
// callback (between hdBeginFrame/hdEndFrame) instead of rp::ServoLoop. Device errors reported by
// hdGetError() make Read() fail, so the servo task's watchdog zeroes the force.
#include <atomic>
#include <cstdint>

#include "rpHapticDevice.h"
#include "rpServoLoop.h"

namespace rp {

class OpenHapticsDevice : public HapticDevice {
 public:
  ~OpenHapticsDevice() override;
  bool Open(std::string& error) override;
  void Close() override;
  const DeviceInfo& Info() const override { return this->Description; }
  bool Read(double time, DeviceState& state) noexcept override;
  void WriteForce(const Vec3& force) noexcept override;

  /// Starts the HD scheduler and calls task->Tick() every servo frame. Stop before Close().
  bool StartScheduler(ServoTask* task, std::string& error);
  void StopScheduler();
  uint64_t DeviceErrors() const { return this->Errors.load(); }

  /// Called by the HD scheduler (internal).
  bool Frame() noexcept;

 private:
  DeviceInfo Description;
  unsigned int Handle = 0;  // HHD
  unsigned long Callback = 0;  // HDSchedulerHandle
  bool IsOpen = false, SchedulerRunning = false;
  ServoTask* Task = nullptr;
  TickInfo Clock;
  std::atomic<bool> StopRequested{false};
  std::atomic<uint64_t> Errors{0};
  bool FrameError = false;
};

}  // namespace rp
