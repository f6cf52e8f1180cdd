#include "rpTimingHistogram.h"

namespace rp {

TimingHistogram::TimingHistogram(int64_t binWidthNs, size_t binCount)
    : Width(binWidthNs > 0 ? binWidthNs : 1), Count(binCount > 0 ? binCount : 1),
      Bins(new std::atomic<uint64_t>[binCount > 0 ? binCount : 1]) {
  this->Reset();
}

void TimingHistogram::Record(int64_t ns) noexcept {
  if (ns < 0) ns = 0;
  size_t bin = static_cast<size_t>(ns / this->Width);
  if (bin >= this->Count) bin = this->Count - 1;
  // Single writer: load+store is enough and cheaper than a locked read-modify-write.
  this->Bins[bin].store(this->Bins[bin].load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  this->SumNs.store(this->SumNs.load(std::memory_order_relaxed) + ns, std::memory_order_relaxed);
  if (ns > this->MaxNs.load(std::memory_order_relaxed)) this->MaxNs.store(ns, std::memory_order_relaxed);
  if (ns < this->MinNs.load(std::memory_order_relaxed)) this->MinNs.store(ns, std::memory_order_relaxed);
  this->Samples.store(this->Samples.load(std::memory_order_relaxed) + 1, std::memory_order_release);
}

void TimingHistogram::Reset() noexcept {
  for (size_t i = 0; i < this->Count; ++i) this->Bins[i].store(0, std::memory_order_relaxed);
  this->SumNs.store(0, std::memory_order_relaxed);
  this->MaxNs.store(0, std::memory_order_relaxed);
  this->MinNs.store(INT64_MAX, std::memory_order_relaxed);
  this->Samples.store(0, std::memory_order_release);
}

double TimingHistogram::PercentileUs(double q) const {
  uint64_t total = 0;
  for (size_t i = 0; i < this->Count; ++i) total += this->Bins[i].load(std::memory_order_relaxed);
  if (total == 0) return 0;
  const double wanted = q * static_cast<double>(total);
  uint64_t seen = 0;
  for (size_t i = 0; i < this->Count; ++i) {
    seen += this->Bins[i].load(std::memory_order_relaxed);
    if (static_cast<double>(seen) >= wanted) {
      if (i == this->Count - 1) return this->MaxNs.load(std::memory_order_relaxed) / 1000.0;
      return static_cast<double>((i + 1) * this->Width) / 1000.0;
    }
  }
  return this->MaxNs.load(std::memory_order_relaxed) / 1000.0;
}

TimingStats TimingHistogram::Stats() const {
  TimingStats s;
  s.Count = this->Samples.load(std::memory_order_acquire);
  if (s.Count == 0) return s;
  s.MeanUs = static_cast<double>(this->SumNs.load(std::memory_order_relaxed)) / s.Count / 1000.0;
  s.MaxUs = this->MaxNs.load(std::memory_order_relaxed) / 1000.0;
  s.MinUs = this->MinNs.load(std::memory_order_relaxed) / 1000.0;
  s.P50Us = this->PercentileUs(0.5);
  s.P99Us = this->PercentileUs(0.99);
  s.P999Us = this->PercentileUs(0.999);
  if (s.P50Us > s.MaxUs) s.P50Us = s.MaxUs;  // bin upper edge past the true maximum
  if (s.P99Us > s.MaxUs) s.P99Us = s.MaxUs;
  if (s.P999Us > s.MaxUs) s.P999Us = s.MaxUs;
  return s;
}

}  // namespace rp
