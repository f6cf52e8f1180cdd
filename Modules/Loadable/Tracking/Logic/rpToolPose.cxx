#include "rpToolPose.h"

#include <chrono>
#include <cmath>

namespace rp {

const char* ToolStateName(ToolState state) {
  switch (state) {
    case ToolState::OK: return "OK";
    case ToolState::Missing: return "MISSING";
    case ToolState::OutOfVolume: return "OUT_OF_VOLUME";
    case ToolState::Disabled: return "DISABLED";
  }
  return "UNKNOWN";
}

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void ToolPose::ToMatrix(double m[16]) const {
  const double w = Quaternion[0], x = Quaternion[1], y = Quaternion[2], z = Quaternion[3];
  m[0] = 1 - 2 * (y * y + z * z);
  m[1] = 2 * (x * y - w * z);
  m[2] = 2 * (x * z + w * y);
  m[4] = 2 * (x * y + w * z);
  m[5] = 1 - 2 * (x * x + z * z);
  m[6] = 2 * (y * z - w * x);
  m[8] = 2 * (x * z - w * y);
  m[9] = 2 * (y * z + w * x);
  m[10] = 1 - 2 * (x * x + y * y);
  m[3] = Translation[0];
  m[7] = Translation[1];
  m[11] = Translation[2];
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
}

void ToolPose::FromMatrix(const double m[16]) {
  // Shepperd's method: pick the largest diagonal combination for numerical stability.
  const double tr = m[0] + m[5] + m[10];
  double w, x, y, z;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    w = 0.25 * s;
    x = (m[9] - m[6]) / s;
    y = (m[2] - m[8]) / s;
    z = (m[4] - m[1]) / s;
  } else if (m[0] > m[5] && m[0] > m[10]) {
    const double s = std::sqrt(1.0 + m[0] - m[5] - m[10]) * 2;
    w = (m[9] - m[6]) / s;
    x = 0.25 * s;
    y = (m[1] + m[4]) / s;
    z = (m[2] + m[8]) / s;
  } else if (m[5] > m[10]) {
    const double s = std::sqrt(1.0 + m[5] - m[0] - m[10]) * 2;
    w = (m[2] - m[8]) / s;
    x = (m[1] + m[4]) / s;
    y = 0.25 * s;
    z = (m[6] + m[9]) / s;
  } else {
    const double s = std::sqrt(1.0 + m[10] - m[0] - m[5]) * 2;
    w = (m[4] - m[1]) / s;
    x = (m[2] + m[8]) / s;
    y = (m[6] + m[9]) / s;
    z = 0.25 * s;
  }
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  if (n > 0) {
    Quaternion[0] = w / n;
    Quaternion[1] = x / n;
    Quaternion[2] = y / n;
    Quaternion[3] = z / n;
  }
  Translation[0] = m[3];
  Translation[1] = m[7];
  Translation[2] = m[11];
}

int ToolPoseTable::Find(const char* name, size_t length) const noexcept {
  const int n = this->NumberOfSlots.load(std::memory_order_acquire);
  if (length >= NameLength) length = NameLength - 1;
  for (int i = 0; i < n; ++i) {
    const char* s = this->Slots[i].Name;
    if (std::strncmp(s, name, length) == 0 && s[length] == '\0') return i;
  }
  return -1;
}

int ToolPoseTable::FindOrAdd(const char* name, size_t length) noexcept {
  if (length >= NameLength) length = NameLength - 1;
  const int found = this->Find(name, length);
  if (found >= 0) return found;
  const int n = this->NumberOfSlots.load(std::memory_order_relaxed);
  if (n >= Capacity) return -1;
  std::memcpy(this->Slots[n].Name, name, length);
  this->Slots[n].Name[length] = '\0';
  this->NumberOfSlots.store(n + 1, std::memory_order_release);
  return n;
}

ToolPoseTable::StateCounts ToolPoseTable::Counts(int slot) const noexcept {
  const auto& n = this->Slots[slot].ByState;
  StateCounts c;
  c.Ok = n[static_cast<int>(ToolState::OK)].load(std::memory_order_relaxed);
  c.Missing = n[static_cast<int>(ToolState::Missing)].load(std::memory_order_relaxed);
  c.OutOfVolume = n[static_cast<int>(ToolState::OutOfVolume)].load(std::memory_order_relaxed);
  c.Disabled = n[static_cast<int>(ToolState::Disabled)].load(std::memory_order_relaxed);
  return c;
}

const ToolPoseReader::Sample& ToolPoseReader::Poll(const ToolPoseTable& table, int slot) {
  Sample& s = this->Samples[slot];
  ToolPose pose;
  const uint64_t count = table.Read(slot, pose);
  s.Fresh = count > s.Received;
  if (s.Fresh) {
    s.Dropped += count - s.Received - 1;
    s.Received = count;
    s.Pose = pose;
    s.Valid = true;
  }
  return s;
}

}  // namespace rp
