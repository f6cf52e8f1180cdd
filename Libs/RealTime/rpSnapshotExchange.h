#pragma once
// Hands immutable snapshots (a haptic scene, a set of virtual fixtures) from their owner thread to
// a real-time thread without locks: the owner Publish()es (any number of times); the real-time
// thread Acquire()s at the start of a tick (wait-free: two atomic exchanges, no allocation, no
// free); the owner deletes snapshots the real-time thread retired in Collect(). At most one
// snapshot is retired at a time, so the real-time thread keeps using its current one until
// Collect() ran.
#include <atomic>
#include <memory>

namespace rp {

template <typename T>
class SnapshotExchange {
 public:
  SnapshotExchange() = default;
  SnapshotExchange(const SnapshotExchange&) = delete;
  SnapshotExchange& operator=(const SnapshotExchange&) = delete;
  ~SnapshotExchange() { this->Clear(); }

  /// Owner thread.
  void Publish(std::unique_ptr<T> snapshot) {
    T* previous = this->Pending.exchange(snapshot.release(), std::memory_order_acq_rel);
    delete previous;  // never taken by the real-time thread
    this->Collect();
  }
  /// Owner thread: frees the snapshot the real-time thread retired.
  void Collect() { delete this->Retired.exchange(nullptr, std::memory_order_acq_rel); }
  /// Real-time thread: the snapshot to use this tick (nullptr: none yet).
  const T* Acquire() noexcept {
    T* current = this->Current.load(std::memory_order_relaxed);
    if (this->Pending.load(std::memory_order_relaxed) == nullptr) return current;
    if (current != nullptr && this->Retired.load(std::memory_order_acquire) != nullptr) return current;  // wait for Collect
    T* next = this->Pending.exchange(nullptr, std::memory_order_acq_rel);
    if (next == nullptr) return current;
    if (current != nullptr) this->Retired.store(current, std::memory_order_release);
    this->Current.store(next, std::memory_order_release);
    return next;
  }
  /// Owner thread, real-time thread stopped: deletes everything.
  void Clear() {
    delete this->Pending.exchange(nullptr);
    delete this->Retired.exchange(nullptr);
    delete this->Current.exchange(nullptr);
  }

 private:
  std::atomic<T*> Pending{nullptr};
  std::atomic<T*> Retired{nullptr};
  std::atomic<T*> Current{nullptr};  // written by the real-time thread only (atomic for Clear)
};

}  // namespace rp
