#pragma once
// Single-writer, many-reader "latest value" exchange (a sequence lock).
// The writer never waits, locks or allocates: a real-time thread (haptic servo loop, tracker
// I/O) publishes its newest state; the main thread reads a consistent copy at display rate.
// T must be trivially copyable. Readers retry while a write is in progress.
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace rp {

template <typename T>
class LatestValue {
  static_assert(std::is_trivially_copyable<T>::value, "LatestValue<T> needs a trivially copyable T");
  static constexpr size_t WordCount = (sizeof(T) + sizeof(uint64_t) - 1) / sizeof(uint64_t);

 public:
  LatestValue() {
    for (auto& w : this->Words) w.store(0, std::memory_order_relaxed);
  }

  /// Writer side (one thread only). Wait-free.
  void Publish(const T& value) noexcept {
    uint64_t buffer[WordCount] = {};
    std::memcpy(buffer, &value, sizeof(T));
    const uint64_t seq = this->Sequence.load(std::memory_order_relaxed);
    this->Sequence.store(seq + 1, std::memory_order_relaxed);  // odd: write in progress
    // Release per word, not a fence (ThreadSanitizer does not model fences): a reader that sees a
    // new word also sees the odd sequence. Plain stores on x86.
    for (size_t i = 0; i < WordCount; ++i) this->Words[i].store(buffer[i], std::memory_order_release);
    this->Sequence.store(seq + 2, std::memory_order_release);  // even: stable
  }

  /// Reader side (any thread). Returns how many values were published so far (0: none yet,
  /// and `out` is left untouched).
  uint64_t Read(T& out) const noexcept {
    uint64_t buffer[WordCount];
    for (;;) {
      const uint64_t before = this->Sequence.load(std::memory_order_acquire);
      if (before == 0) return 0;
      if (before & 1u) continue;  // writer mid-copy
      // Acquire per word: the sequence read after them is at least as new as any word read.
      for (size_t i = 0; i < WordCount; ++i) buffer[i] = this->Words[i].load(std::memory_order_acquire);
      if (this->Sequence.load(std::memory_order_relaxed) == before) {
        std::memcpy(&out, buffer, sizeof(T));
        return before / 2;
      }
    }
  }

  uint64_t PublishCount() const noexcept { return this->Sequence.load(std::memory_order_acquire) / 2; }

 private:
  alignas(64) std::atomic<uint64_t> Sequence{0};
  alignas(64) std::atomic<uint64_t> Words[WordCount];
};

}  // namespace rp
