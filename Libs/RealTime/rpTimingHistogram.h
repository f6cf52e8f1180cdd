#pragma once
// A fixed-bin histogram of durations (nanoseconds) written by one real-time thread and read by
// any other: relaxed atomic counters, no allocation after construction, no locks.
#include <atomic>
#include <cstdint>
#include <memory>

namespace rp {

struct TimingStats {
  uint64_t Count = 0;
  double MeanUs = 0, P50Us = 0, P99Us = 0, P999Us = 0, MaxUs = 0, MinUs = 0;
};

class TimingHistogram {
 public:
  /// `binWidthNs` wide bins from 0 to binWidthNs*binCount; larger values go to the last bin (the
  /// exact maximum is kept separately).
  TimingHistogram(int64_t binWidthNs, size_t binCount);
  void Record(int64_t ns) noexcept;  // writer thread only
  void Reset() noexcept;             // not concurrently with Record
  TimingStats Stats() const;         // any thread; approximate while the writer runs
  /// Value (µs) below which a fraction q of the samples lie (bin upper edge).
  double PercentileUs(double q) const;
  size_t BinCount() const { return this->Count; }
  int64_t BinWidthNs() const { return this->Width; }
  uint64_t BinValue(size_t i) const { return this->Bins[i].load(std::memory_order_relaxed); }

 private:
  int64_t Width;
  size_t Count;
  std::unique_ptr<std::atomic<uint64_t>[]> Bins;
  std::atomic<uint64_t> Samples{0};
  std::atomic<int64_t> SumNs{0}, MaxNs{0}, MinNs{INT64_MAX};
};

}  // namespace rp
