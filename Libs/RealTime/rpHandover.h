#pragma once
// Hands whole objects built off the servo thread (the haptic scene, the virtual fixtures of a
// plan) to the servo thread without locks: the owner Publish()es any number of times; the servo
// thread Acquire()s at the start of a tick (wait-free: two atomic exchanges, no allocation, no
// free); the owner deletes what the servo thread retired in Collect(). At most one object is
// retired at a time, so the servo thread keeps its current one until Collect() ran. The object
// the servo thread holds is its own until retired (it may keep state in it).
#include <atomic>
#include <memory>

namespace rp {

template <typename T>
class Handover {
 public:
  Handover() = default;
  Handover(const Handover&) = delete;
  Handover& operator=(const Handover&) = delete;
  ~Handover() { this->Clear(); }

  /// Owner thread: the next object for the servo thread (a newer one replaces one not taken yet).
  void Publish(std::unique_ptr<T> next) {
    delete this->Pending.exchange(next.release(), std::memory_order_acq_rel);  // never taken
    this->Collect();
  }
  /// Owner thread: frees what the servo thread retired.
  void Collect() { delete this->Retired.exchange(nullptr, std::memory_order_acq_rel); }
  /// Servo thread: the object to use this tick (nullptr: none yet).
  T* Acquire() noexcept {
    return this->Acquire([](T&, const T&) noexcept {});
  }
  /// The same; when a new object replaces the current one, `carry(next, previous)` runs first
  /// (on the servo thread, before `previous` is retired): state that must survive the swap, e.g.
  /// a fixture holding the tool, is copied there. It must not allocate.
  template <typename Carry>
  T* Acquire(Carry&& carry) noexcept {
    T* current = this->Current.load(std::memory_order_relaxed);
    if (this->Pending.load(std::memory_order_relaxed) == nullptr) return current;
    if (current != nullptr && this->Retired.load(std::memory_order_acquire) != nullptr) return current;  // wait for Collect
    T* next = this->Pending.exchange(nullptr, std::memory_order_acq_rel);
    if (next == nullptr) return current;
    if (current != nullptr) {
      carry(*next, static_cast<const T&>(*current));
      this->Retired.store(current, std::memory_order_release);
    }
    this->Current.store(next, std::memory_order_release);
    return next;
  }
  /// Owner thread, servo stopped: deletes everything.
  void Clear() {
    delete this->Pending.exchange(nullptr);
    delete this->Retired.exchange(nullptr);
    delete this->Current.exchange(nullptr);
  }

 private:
  std::atomic<T*> Pending{nullptr};
  std::atomic<T*> Retired{nullptr};
  std::atomic<T*> Current{nullptr};  // written by the servo thread only (atomic for Clear)
};

}  // namespace rp
