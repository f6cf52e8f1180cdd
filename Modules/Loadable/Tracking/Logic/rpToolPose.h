#pragma once
// A timestamped 6-DoF pose of one tracked tool, as an I/O thread publishes it, and a fixed-size
// table of named slots that one I/O thread writes and the main thread reads, lock-free.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <string>

#include "rpLatestValue.h"

namespace rp {

enum class ToolState : uint8_t { OK = 0, Missing, OutOfVolume, Disabled };
const char* ToolStateName(ToolState state);

struct ToolPose {
  double Timestamp = 0.0;          // seconds; tracker/host clock of the measurement
  double ReceiveTime = 0.0;        // seconds, steady clock of this host when it arrived
  double Quaternion[4] = {1, 0, 0, 0};  // w x y z (unit)
  double Translation[3] = {0, 0, 0};    // mm
  double Error = -1.0;             // tracker RMS fit error, mm (negative: unknown)
  uint32_t Frame = 0;              // tracker frame number (0 when not given)
  uint32_t PortStatus = 0;
  ToolState State = ToolState::Missing;

  /// Row-major 4x4 "to parent" matrix of the pose.
  void ToMatrix(double m[16]) const;
  /// From a row-major rotation+translation (the rotation is re-orthonormalised via quaternion).
  void FromMatrix(const double m[16]);
};

/// Seconds of a monotonic clock (steady_clock); every receive time uses it.
double SteadySeconds();
/// Seconds since 1970 (system clock).
double WallSeconds();

/// Named slots (up to Capacity) of newest poses. Exactly one writer thread registers names and
/// publishes; any number of readers. Registration is append-only: a slot's name is written
/// before Count is released, so a reader that sees Count also sees the names.
class ToolPoseTable {
 public:
  static constexpr int Capacity = 64;
  static constexpr int NameLength = 64;

  /// Writer: slot of a name, registering it when new; -1 when the table is full.
  int FindOrAdd(const char* name, size_t length) noexcept;
  int FindOrAdd(const char* name) noexcept { return this->FindOrAdd(name, std::strlen(name)); }
  /// Writer only (no lock): slot of a name or -1.
  int Find(const char* name, size_t length) const noexcept;
  /// Writer: the newest pose of a slot (also counted by its state).
  void Publish(int slot, const ToolPose& pose) noexcept {
    std::atomic<uint64_t>& n = this->Slots[slot].ByState[static_cast<int>(pose.State) & 3];
    n.store(n.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);  // one writer
    this->Slots[slot].Pose.Publish(pose);
  }

  /// Reader side.
  int Count() const noexcept { return this->NumberOfSlots.load(std::memory_order_acquire); }
  const char* Name(int slot) const noexcept { return this->Slots[slot].Name; }
  /// Returns how many poses were published to the slot so far (0: none yet).
  uint64_t Read(int slot, ToolPose& pose) const noexcept { return this->Slots[slot].Pose.Read(pose); }
  /// Every pose published to a slot, by state (also those no reader saw).
  struct StateCounts {
    uint64_t Ok = 0, Missing = 0, OutOfVolume = 0, Disabled = 0;
    uint64_t WithPose() const { return this->Ok + this->OutOfVolume; }  // frames that carry a pose
  };
  StateCounts Counts(int slot) const noexcept;

 private:
  struct Slot {
    char Name[NameLength] = {};
    LatestValue<ToolPose> Pose;
    std::atomic<uint64_t> ByState[4] = {};  // poses published, by ToolState
  };
  std::array<Slot, Capacity> Slots;
  std::atomic<int> NumberOfSlots{0};
};

/// Main-thread helper: reads each slot and counts poses that were overwritten before anybody
/// read them (the "dropped" count of keep-newest-per-tool).
class ToolPoseReader {
 public:
  struct Sample {
    bool Fresh = false;        // a pose newer than the last Poll
    bool Valid = false;        // any pose at all
    ToolPose Pose;
    uint64_t Received = 0;     // poses published so far
    uint64_t Dropped = 0;      // published but never seen by this reader
  };
  /// Reads slot i (after the caller checked i < table.Count()).
  const Sample& Poll(const ToolPoseTable& table, int slot);
  const Sample& Last(int slot) const { return this->Samples[slot]; }

 private:
  std::array<Sample, ToolPoseTable::Capacity> Samples;
};

}  // namespace rp
