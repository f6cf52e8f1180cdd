#include "rpOpenHapticsDevice.h"

#include <HD/hd.h>

#include <chrono>

namespace rp {

namespace {
HDCallbackCode HDCALLBACK ServoCallback(void* data) {
  auto* device = static_cast<OpenHapticsDevice*>(data);
  return device->Frame() ? HD_CALLBACK_CONTINUE : HD_CALLBACK_DONE;
}
bool Failed(std::string* error, const char* what) {
  const HDErrorInfo info = hdGetError();
  if (!HD_DEVICE_ERROR(info)) return false;
  if (error) *error = std::string("OpenHaptics: ") + what + ": " + hdGetErrorString(info.errorCode);
  return true;
}
}  // namespace

OpenHapticsDevice::~OpenHapticsDevice() { this->Close(); }

bool OpenHapticsDevice::Open(std::string& error) {
  if (this->IsOpen) return true;
  this->Handle = hdInitDevice(HD_DEFAULT_DEVICE);
  if (Failed(&error, "cannot initialise the default device")) return false;
  hdMakeCurrentDevice(this->Handle);
  hdEnable(HD_FORCE_OUTPUT);
  this->Description.Name = hdGetString(HD_DEVICE_MODEL_TYPE) ? hdGetString(HD_DEVICE_MODEL_TYPE) : "OpenHaptics device";
  HDdouble value = 0;
  hdGetDoublev(HD_NOMINAL_MAX_FORCE, &value);
  if (value > 0) this->Description.MaxForce = value;
  hdGetDoublev(HD_NOMINAL_MAX_STIFFNESS, &value);
  if (value > 0) this->Description.NominalMaxStiffness = value;
  hdGetDoublev(HD_NOMINAL_MAX_DAMPING, &value);
  if (value > 0) this->Description.NominalMaxDamping = value;
  // The HD API does not report the mechanism's own damping: rely on the nominal limits.
  this->Description.PhysicalDamping = 0;
  HDdouble workspace[6];
  hdGetDoublev(HD_USABLE_WORKSPACE_DIMENSIONS, workspace);
  this->Description.WorkspaceMin = {workspace[0], workspace[1], workspace[2]};
  this->Description.WorkspaceMax = {workspace[3], workspace[4], workspace[5]};
  if (Failed(&error, "cannot read the device limits")) {
    hdDisableDevice(this->Handle);
    return false;
  }
  this->IsOpen = true;
  return true;
}

void OpenHapticsDevice::Close() {
  this->StopScheduler();
  if (!this->IsOpen) return;
  hdDisableDevice(this->Handle);
  this->IsOpen = false;
}

bool OpenHapticsDevice::StartScheduler(ServoTask* task, std::string& error) {
  if (!this->IsOpen || task == nullptr) {
    error = "OpenHaptics: open the device and give a task first";
    return false;
  }
  this->Task = task;
  this->Clock = TickInfo{};
  this->StopRequested.store(false);
  task->ServoStarted();
  this->Callback = hdScheduleAsynchronous(ServoCallback, this, HD_MAX_SCHEDULER_PRIORITY);
  hdStartScheduler();
  if (Failed(&error, "cannot start the servo scheduler")) return false;
  this->SchedulerRunning = true;
  return true;
}

void OpenHapticsDevice::StopScheduler() {
  if (!this->SchedulerRunning) return;
  this->StopRequested.store(true);
  hdStopScheduler();
  hdUnschedule(this->Callback);
  this->SchedulerRunning = false;
  if (this->Task) this->Task->ServoStopping();
}

bool OpenHapticsDevice::Frame() noexcept {
  const auto start = std::chrono::steady_clock::now();
  hdBeginFrame(this->Handle);
  this->FrameError = Failed(nullptr, "frame");
  HDdouble rate = 1000;
  hdGetDoublev(HD_INSTANTANEOUS_UPDATE_RATE, &rate);
  this->Clock.Period = rate > 0 ? 1.0 / rate : 1e-3;
  this->Task->Tick(this->Clock);  // calls Read() and WriteForce() inside the frame
  hdEndFrame(this->Handle);
  if (Failed(nullptr, "end frame")) this->Errors.fetch_add(1);
  const auto compute = std::chrono::steady_clock::now() - start;
  this->Clock.PreviousComputeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(compute).count();
  this->Clock.PreviousOverran = this->Clock.PreviousComputeNs > static_cast<int64_t>(this->Clock.Period * 1e9);
  this->Clock.Time += this->Clock.Period;
  ++this->Clock.Index;
  return !this->StopRequested.load(std::memory_order_relaxed);
}

bool OpenHapticsDevice::Read(double, DeviceState& state) noexcept {
  if (this->FrameError) {
    this->Errors.fetch_add(1);
    return false;
  }
  HDdouble m[16], v[3];
  HDint buttons = 0;
  hdGetDoublev(HD_CURRENT_TRANSFORM, m);  // column-major, translation in mm
  hdGetDoublev(HD_CURRENT_VELOCITY, v);
  hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) state.StylusToDevice.R[3 * r + c] = m[4 * c + r];
  state.StylusToDevice.T = {m[12], m[13], m[14]};
  state.Velocity = {v[0], v[1], v[2]};
  state.Buttons = static_cast<uint32_t>(buttons);
  return true;
}

void OpenHapticsDevice::WriteForce(const Vec3& force) noexcept {
  const HDdouble f[3] = {force.x, force.y, force.z};
  hdSetDoublev(HD_CURRENT_FORCE, f);
}

}  // namespace rp
