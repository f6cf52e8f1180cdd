#pragma once
// Messages the main thread hands to an OpenIGTLink server to send to every client: the newest of
// each named TRANSFORM or STRING (e.g. the navigation read-outs: ToolTipToTrajectory and
// GuidanceReadout). One writer thread publishes (wait-free, no allocation after a name's first
// use); the server's thread reads each message's newest content and is woken at once through
// ReadyFd(), so a message leaves within the server's poll turn, not at its next send tick.
#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "rpLatestValue.h"
#include "rpWorkerThread.h"

namespace rp {

class IgtlOutbox {
 public:
  static constexpr int MaxMessages = 8;        // names
  static constexpr size_t MaxContent = 2048;   // bytes of a message's content (a STRING of ~2 KB)
  static constexpr size_t MaxName = 63;        // device name (beyond 20 characters: IGTL_DEVICE_NAME metadata)

  struct Message {
    char Type[13] = {};
    char Name[MaxName + 1] = {};
    uint32_t ContentSize = 0;
    uint8_t Content[MaxContent];
  };

  /// Writer thread: the newest row-major From→To matrix under `name`. False (nothing sent) when
  /// the name is too long or MaxMessages names are in use already.
  bool PublishTransform(const std::string& name, const double m[16]);
  /// Writer thread: the newest text under `name` (US-ASCII). False when too long (see above).
  bool PublishString(const std::string& name, const std::string& text);

  /// Reader thread: how many names are in use; a slot's newest message and its publish count
  /// (0: never published).
  int Count() const { return this->Used.load(std::memory_order_acquire); }
  uint64_t Read(int slot, Message& out) const { return this->Slots[static_cast<size_t>(slot)].Read(out); }
  /// Readable after a publish until DrainReady().
  int ReadyFd() const { return this->Ready.Fd(); }
  void DrainReady() const { this->Ready.Drain(); }

 private:
  Message* Begin(const char* type, const std::string& name);  // writer only
  void Finish(int slot);

  std::array<LatestValue<Message>, MaxMessages> Slots;
  std::atomic<int> Used{0};
  // Writer only: each slot's type and name, and the message being composed.
  char KeyTypes[MaxMessages][13] = {};
  char KeyNames[MaxMessages][MaxName + 1] = {};
  Message Pending;
  int PendingSlot = -1;
  ReadySignal Ready;
};

}  // namespace rp
