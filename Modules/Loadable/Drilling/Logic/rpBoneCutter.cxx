#include "rpBoneCutter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rp {

BoneCutter::BoneCutter(DrillVolume& volume) : BoneCutter(volume, Options{}) {}

BoneCutter::BoneCutter(DrillVolume& volume, const Options& options) : Volume(volume), Settings(options) {
  this->Settings.UndoBlocks = std::max<size_t>(1, options.UndoBlocks);
  this->Settings.MaxStrokes = std::max(1, options.MaxStrokes);
  this->Settings.RestoreBlocksPerTick = std::max(1, options.RestoreBlocksPerTick);
  this->Pool.assign(this->Settings.UndoBlocks * DrillVolume::BlockVoxels, 0);
  this->PoolSlots.assign(this->Settings.UndoBlocks, -1);
  this->Strokes.assign(size_t(this->Settings.MaxStrokes), Stroke{});
  this->Stamps.assign(volume.AllocatedBlocks(), 0);
}

BoneCutter::Stroke& BoneCutter::StrokeAt(int fromNewest) noexcept {
  const int n = this->Settings.MaxStrokes;
  return this->Strokes[size_t(((this->StrokeNewest - fromNewest) % n + n) % n)];
}

double BoneCutter::Removed(int material) const noexcept {
  if (material < 0 || material >= DrillVolume::MaxMaterials) return 0;
  return this->RemovedUnits[material] / 255.0 * this->Volume.VoxelVolume();
}

double BoneCutter::RemovedTotal() const noexcept {
  int64_t units = 0;
  for (int64_t u : this->RemovedUnits) units += u;
  return units / 255.0 * this->Volume.VoxelVolume();
}

void BoneCutter::BeginStroke() noexcept {
  if (this->Stroking) return;
  ++this->StrokeId;
  this->Stroking = true;
  if (this->StrokeCount == this->Settings.MaxStrokes) {  // forget the oldest
    this->Tail = this->StrokeAt(this->StrokeCount - 1).End;
    --this->StrokeCount;
  }
  this->StrokeNewest = (this->StrokeNewest + 1) % this->Settings.MaxStrokes;
  ++this->StrokeCount;
  Stroke& s = this->StrokeAt(0);
  s.Begin = s.End = this->Head;
  std::memcpy(s.RemovedBefore, this->RemovedUnits, sizeof(this->RemovedUnits));
  s.Kept = true;
}

void BoneCutter::EndStroke() noexcept {
  this->FinishCut();  // what the stroke began belongs to it (and to its undo)
  if (!this->Stroking) return;
  this->Stroking = false;
  Stroke& s = this->StrokeAt(0);
  s.End = s.Kept ? this->Head : s.Begin;
  this->Lost = !s.Kept;
  if (std::memcmp(s.RemovedBefore, this->RemovedUnits, sizeof(this->RemovedUnits)) == 0) {
    // Nothing removed: not a stroke worth undoing.
    this->Head = s.Begin;
    this->StrokeNewest = (this->StrokeNewest - 1 + this->Settings.MaxStrokes) % this->Settings.MaxStrokes;
    --this->StrokeCount;
    this->Lost = false;
  }
}

void BoneCutter::Snapshot(int32_t slot) noexcept {
  if (!this->Stroking || this->Stamps[size_t(slot)] == this->StrokeId) return;
  this->Stamps[size_t(slot)] = this->StrokeId;
  Stroke& s = this->StrokeAt(0);
  if (!s.Kept) return;
  const size_t capacity = this->PoolSlots.size();
  while (this->Head - this->Tail == capacity && this->StrokeCount > 1) {  // make room: forget the oldest
    this->Tail = this->StrokeAt(this->StrokeCount - 1).End;
    --this->StrokeCount;
  }
  if (this->Head - this->Tail == capacity) {  // this stroke alone fills the pool: it cannot be undone
    s.Kept = false;
    this->Head = this->Tail = s.Begin;
    return;
  }
  const size_t entry = this->Head % capacity;
  const std::atomic<uint8_t>* densities = this->Volume.BlockDensities(slot);
  uint8_t* copy = &this->Pool[entry * DrillVolume::BlockVoxels];
  for (int v = 0; v < DrillVolume::BlockVoxels; ++v) copy[v] = densities[v].load(std::memory_order_relaxed);
  this->PoolSlots[entry] = slot;
  ++this->Head;
  s.End = this->Head;
}

bool BoneCutter::ReachesProtected(const Vec3& center, double radius) const noexcept {
  const double h = this->Volume.Spacing();
  const double reach = radius + h;
  const DrillGrid& grid = this->Volume.Grid();
  bool reached = false;
  this->Volume.ForEachBlock(
      this->Volume.BoxAround(center - Vec3{reach, reach, reach}, center + Vec3{reach, reach, reach}),
      [&](int32_t slot, const int lo[3], const int hi[3]) {
        if (reached || !this->Volume.BlockHasProtected(slot)) return;
        const std::atomic<uint8_t>* densities = this->Volume.BlockDensities(slot);
        const uint8_t* codes = this->Volume.BlockMaterials(slot);
        for (int k = lo[2]; k <= hi[2] && !reached; ++k)
          for (int j = lo[1]; j <= hi[1] && !reached; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i) {
              const int local = DrillVolume::Local(i, j, k);
              if (!(codes[local] & DrillVolume::ProtectedBit)) continue;
              const double distance = Norm(grid.Center(i, j, k) - center);
              const uint8_t q = densities[local].load(std::memory_order_relaxed);
              // A protected bone voxel the carve would thin, or protected space inside the burr.
              if ((q > 0 && distance < reach && DrillVolume::Quantize(DrillVolume::RampDensity(radius - distance, h)) < q) ||
                  (q == 0 && distance < radius)) {
                reached = true;
                break;
              }
            }
      });
  return reached;
}

CutResult BoneCutter::Cut(const Vec3& center, double radius, const Vec3& direction, double advance) noexcept {
  CutResult result = this->BeginCut(center, radius, direction, advance, 1);
  this->FinishCut();
  return result;
}

CutResult BoneCutter::BeginCut(const Vec3& center, double radius, const Vec3& direction, double advance,
                               int slices) noexcept {
  this->FinishCut();
  CutResult result;
  if (this->Mode != RestoreMode::None) return result;
  if (this->ReachesProtected(center, radius)) {
    result.Refused = true;
    return result;
  }
  PendingCut& job = this->Job;
  const double h = this->Volume.Spacing();
  const double reach = radius + h;
  job.Center = center;
  job.Radius = radius;
  job.Incremental = Norm2(direction) > 0;
  // Closer than r − h − advance to the new centre is within r − h of the last one: empty.
  job.Inner = job.Incremental ? std::max(0.0, radius - h - advance - 1e-9) : 0.0;
  // Nearer the last centre than the new one (behind the bisecting plane): already carved.
  job.Ahead = DrillVolume::HalfSpace{direction, -0.5 * advance - 1e-9};
  // Only the side of the bisecting plane nearer the new centre can change: the rows are limited
  // to the bounding box of that cap of the ball (about half of it).
  job.Lo = center - Vec3{reach, reach, reach};
  job.Hi = center + Vec3{reach, reach, reach};
  if (job.Incremental) {
    const double e = 0.5 * advance + 1e-9;
    for (int a = 0; a < 3; ++a) {
      const double side = reach * std::sqrt(std::max(0.0, 1.0 - direction[a] * direction[a])) + e;
      if (direction[a] < -e / reach) job.Hi[a] = center[a] + std::min(reach, side);
      if (direction[a] > e / reach) job.Lo[a] = center[a] - std::min(reach, side);
    }
  }
  job.Slices = std::max(1, slices);
  job.Next = 0;
  return this->ContinueCut();
}

CutResult BoneCutter::ContinueCut() noexcept {
  CutResult result;
  PendingCut& job = this->Job;
  if (job.Next >= job.Slices) return result;
  const double h = this->Volume.Spacing();
  const double radius = job.Radius, reach = radius + h, reach2 = reach * reach, half = 0.5 / h;
  int64_t units = 0;
  int32_t snapped = -1;
  const DrillVolume::RowSlice rows{job.Slices, job.Next++};
  this->Volume.ForEachRunInShell(job.Center, job.Inner, reach, job.Incremental ? &job.Ahead : nullptr, job.Lo, job.Hi,
                                 rows, [&](int32_t slot, int local, int count, const Vec3& w) {
    std::atomic<uint8_t>* densities = this->Volume.BlockDensities(slot);
    // Read as plain bytes: this thread is the densities' only writer (the display thread reads them atomically).
    const uint8_t* current = reinterpret_cast<const uint8_t*>(densities);
    const uint8_t* codes = this->Volume.BlockMaterials(slot);
    const double row2 = w.y * w.y + w.z * w.z;
    double wx = w.x;
    for (int at = local, end = local + count; at < end; ++at, wx += h) {
      const uint8_t q = current[at];
      if (q == 0) continue;
      const double d2 = wx * wx + row2;
      if (d2 >= reach2) continue;
      // What the ramp around the sphere leaves: ρ = ½ + (|w| − r) / 2h (DrillVolume::RampDensity
      // of r − |w|), quantized as DrillVolume::Quantize does.
      const double rho = 0.5 + (std::sqrt(d2) - radius) * half;
      const uint8_t target = rho <= 0 ? uint8_t(0) : rho >= 1 ? uint8_t(255) : static_cast<uint8_t>(rho * 255.0 + 0.5);
      const uint8_t code = codes[at];
      if (target >= q || (code & DrillVolume::ProtectedBit)) continue;
      if (slot != snapped) this->Snapshot(slot), snapped = slot;
      densities[at].store(target, std::memory_order_relaxed);
      const int m = code & DrillVolume::MaterialMask;
      if (m > 0) this->RemovedUnits[m - 1] += q - target;
      units += q - target;
    }
  });
  if (units > 0) {
    // The voxels that changed lie in the cap's box (cheaper than a box per voxel; the same blocks).
    this->Volume.MarkDirty(this->Volume.BoxAround(job.Lo, job.Hi));
    result.Removed = true;
    result.VolumeMm3 = units / 255.0 * this->Volume.VoxelVolume();
  }
  return result;
}

void BoneCutter::FinishCut() noexcept {
  while (this->CutPending()) this->ContinueCut();
}

bool BoneCutter::StartUndo() noexcept {
  if (this->Mode != RestoreMode::None) return false;
  this->EndStroke();
  if (this->StrokeCount == 0) return false;
  Stroke& s = this->StrokeAt(0);
  if (!s.Kept) {
    // Undoing older strokes would leave this one half in place: nothing is undoable any more.
    this->StrokeCount = 0;
    this->Tail = this->Head;
    return false;
  }
  this->Mode = RestoreMode::Undo;
  this->RestoreNext = s.End;
  this->RestoreEnd = s.Begin;
  return true;
}

void BoneCutter::StartReset() noexcept {
  this->Job.Next = this->Job.Slices;  // a pending cut is dropped: all of it comes back
  this->Stroking = false;
  this->Mode = RestoreMode::Reset;
  this->RestoreNext = 0;
  this->RestoreEnd = this->Volume.AllocatedBlocks();
}

void BoneCutter::RestoreBlock(int32_t slot, const uint8_t* data) noexcept {
  std::atomic<uint8_t>* densities = this->Volume.BlockDensities(slot);
  bool changed = false;
  for (int v = 0; v < DrillVolume::BlockVoxels; ++v) {
    if (densities[v].load(std::memory_order_relaxed) == data[v]) continue;
    densities[v].store(data[v], std::memory_order_relaxed);
    changed = true;
  }
  if (!changed) return;
  const auto& c = this->Volume.BlockCoordinate(slot);
  VoxelBox box;
  for (int a = 0; a < 3; ++a) {
    box.Lo[a] = c[a] * DrillVolume::BlockEdge;
    box.Hi[a] = box.Lo[a] + DrillVolume::BlockEdge - 1;
  }
  this->Volume.MarkDirty(box);
}

void BoneCutter::Step() noexcept {
  int budget = this->Settings.RestoreBlocksPerTick;
  if (this->Mode == RestoreMode::Undo) {
    const size_t capacity = this->PoolSlots.size();
    while (this->RestoreNext > this->RestoreEnd && budget-- > 0) {
      const size_t entry = --this->RestoreNext % capacity;
      this->RestoreBlock(this->PoolSlots[entry], &this->Pool[entry * DrillVolume::BlockVoxels]);
    }
    if (this->RestoreNext == this->RestoreEnd) {
      Stroke& s = this->StrokeAt(0);
      std::memcpy(this->RemovedUnits, s.RemovedBefore, sizeof(this->RemovedUnits));
      this->Head = s.Begin;
      this->StrokeNewest = (this->StrokeNewest - 1 + this->Settings.MaxStrokes) % this->Settings.MaxStrokes;
      --this->StrokeCount;
      this->Mode = RestoreMode::None;
    }
  } else if (this->Mode == RestoreMode::Reset) {
    while (this->RestoreNext < this->RestoreEnd && budget-- > 0) {
      const int32_t slot = static_cast<int32_t>(this->RestoreNext++);
      this->RestoreBlock(slot, this->Volume.BlockOriginal(slot));
    }
    if (this->RestoreNext == this->RestoreEnd) {
      std::memset(this->RemovedUnits, 0, sizeof(this->RemovedUnits));
      this->StrokeCount = 0;
      this->Head = this->Tail = 0;
      this->Lost = false;
      this->Mode = RestoreMode::None;
    }
  }
}

}  // namespace rp
