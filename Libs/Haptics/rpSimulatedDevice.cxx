#include "rpSimulatedDevice.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "rpDeviceProfiles.h"

namespace rp {

bool WaypointTrajectory::Set(const std::vector<double>& times, const std::vector<Vec3>& points, std::string& error) {
  if (times.size() != points.size() || times.empty()) {
    error = "trajectory: needs as many times as points, at least one";
    return false;
  }
  for (size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]) || !std::isfinite(points[i].x) || !std::isfinite(points[i].y) ||
        !std::isfinite(points[i].z)) {
      error = "trajectory: waypoint " + std::to_string(i) + " is not finite";
      return false;
    }
    if (i > 0 && times[i] <= times[i - 1]) {
      error = "trajectory: waypoint " + std::to_string(i) + " time " + std::to_string(times[i]) +
              " does not increase";
      return false;
    }
  }
  this->Times = times;
  this->Positions = points;
  return true;
}

bool WaypointTrajectory::LoadCSV(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "trajectory: cannot open '" + path + "'";
    return false;
  }
  std::vector<double> times;
  std::vector<Vec3> points;
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    double t, x, y, z;
    if (!(fields >> t >> x >> y >> z)) {
      if (times.empty() && lineNumber == 1) continue;  // header
      error = "trajectory: '" + path + "' line " + std::to_string(lineNumber) + " is not 't,x,y,z'";
      return false;
    }
    times.push_back(t);
    points.push_back({x, y, z});
  }
  if (times.empty()) {
    error = "trajectory: '" + path + "' has no waypoints";
    return false;
  }
  if (!this->Set(times, points, error)) {
    error = "'" + path + "': " + error;
    return false;
  }
  return true;
}

void WaypointTrajectory::Evaluate(double t, Pose& pose, Vec3& velocity) const noexcept {
  pose = this->Orientation;
  velocity = Vec3{};
  if (this->Times.empty()) return;
  if (t <= this->Times.front()) {
    pose.T = this->Positions.front();
    return;
  }
  if (t >= this->Times.back()) {
    pose.T = this->Positions.back();
    return;
  }
  const size_t i = static_cast<size_t>(std::upper_bound(this->Times.begin(), this->Times.end(), t) - this->Times.begin());
  const double t0 = this->Times[i - 1], t1 = this->Times[i];
  const Vec3 &p0 = this->Positions[i - 1], &p1 = this->Positions[i];
  const double u = (t - t0) / (t1 - t0);
  pose.T = p0 + (p1 - p0) * u;
  velocity = (p1 - p0) / (t1 - t0);
}

std::shared_ptr<WaypointTrajectory> WaypointTrajectory::Line(const Vec3& a, const Vec3& b, double speed, double start) {
  auto path = std::make_shared<WaypointTrajectory>();
  std::string error;
  const double duration = Norm(b - a) / (speed > 0 ? speed : 1.0);
  if (start > 0)
    path->Set({0.0, start, start + std::max(duration, 1e-6)}, {a, a, b}, error);
  else
    path->Set({0.0, std::max(duration, 1e-6)}, {a, b}, error);
  return path;
}

DeviceInfo SimulatedDevice::DefaultInfo() { return DeviceProfiles().front().Info; }

SimulatedDevice::SimulatedDevice(DeviceInfo info) : Description(std::move(info)) {}

bool SimulatedDevice::Open(std::string& error) {
  if (this->Description.MaxForce <= 0) {
    error = "simulated device: maximum force must be positive";
    return false;
  }
  this->IsOpen = true;
  return true;
}

bool SimulatedDevice::Read(double time, DeviceState& state) noexcept {
  if (this->Fault.load(std::memory_order_relaxed)) return false;
  state.Buttons = this->ButtonState.load(std::memory_order_relaxed);
  if (this->Path) {
    this->Path->Evaluate(time, state.StylusToDevice, state.Velocity);
    if (this->Hand) {
      const Pose intent = state.StylusToDevice;
      const Vec3 intentVelocity = state.Velocity;
      state.StylusToDevice = this->Hand->Step(time, intent, intentVelocity, this->HeldForce, state.Velocity);
    }
    return true;
  }
  Pose pose;
  if (this->Manual.Read(pose) == 0) pose = Pose{};
  state.StylusToDevice = pose;
  state.Velocity = (this->PreviousTime >= 0 && time > this->PreviousTime)
                       ? (pose.T - this->PreviousManual) / (time - this->PreviousTime)
                       : Vec3{};
  this->PreviousManual = pose.T;
  this->PreviousTime = time;
  return true;
}

void SimulatedDevice::WriteForce(const Vec3& force) noexcept {
  this->HeldForce = force;
  this->LastForceValue.Publish(force);
}

Vec3 SimulatedDevice::LastForce() const {
  Vec3 f;
  this->LastForceValue.Read(f);
  return f;
}

}  // namespace rp
