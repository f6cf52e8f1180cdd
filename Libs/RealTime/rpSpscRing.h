#pragma once
// Lock-free single-producer / single-consumer ring of fixed capacity (a power of two). The
// producer (a real-time thread) never blocks or allocates: when the ring is full the record is
// dropped and counted.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace rp {

template <typename T, size_t Capacity>
class SpscRing {
  static_assert((Capacity & (Capacity - 1)) == 0, "Capacity must be a power of two");
  static_assert(std::is_trivially_copyable<T>::value, "SpscRing<T> needs a trivially copyable T");

 public:
  bool TryPush(const T& value) noexcept {
    const size_t head = this->Head.load(std::memory_order_relaxed);
    if (head - this->Tail.load(std::memory_order_acquire) >= Capacity) {
      this->Dropped.store(this->Dropped.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
      return false;
    }
    this->Items[head & (Capacity - 1)] = value;
    this->Head.store(head + 1, std::memory_order_release);
    return true;
  }
  bool TryPop(T& value) noexcept {
    const size_t tail = this->Tail.load(std::memory_order_relaxed);
    if (tail == this->Head.load(std::memory_order_acquire)) return false;
    value = this->Items[tail & (Capacity - 1)];
    this->Tail.store(tail + 1, std::memory_order_release);
    return true;
  }
  uint64_t DroppedCount() const noexcept { return this->Dropped.load(std::memory_order_relaxed); }

 private:
  alignas(64) std::atomic<size_t> Head{0};
  alignas(64) std::atomic<size_t> Tail{0};
  alignas(64) std::atomic<uint64_t> Dropped{0};
  std::array<T, Capacity> Items{};
};

}  // namespace rp
