#include "rpDrillVolume.h"

#include <algorithm>

namespace rp {

DrillVolume::DrillVolume() : Dirty(std::make_unique<DirtyRing>()) {}
DrillVolume::~DrillVolume() = default;

bool DrillVolume::Initialize(const DrillGrid& grid, const std::vector<Material>& materials, std::string& error) {
  if (!(grid.Spacing > 0) || !std::isfinite(grid.Spacing)) {
    error = "drill volume: the voxel size must be positive";
    return false;
  }
  for (int a = 0; a < 3; ++a)
    if (grid.Dimensions[a] < 2) {
      error = "drill volume: the grid needs at least 2 voxels along each axis";
      return false;
    }
  if (grid.VoxelCount() > (size_t(1) << 34)) {
    error = "drill volume: " + std::to_string(grid.VoxelCount()) + " voxels is too many (use a larger --voxel or a region)";
    return false;
  }
  if (materials.empty() || materials.size() > size_t(MaxMaterials)) {
    error = "drill volume: needs 1 to " + std::to_string(MaxMaterials) + " drillable materials";
    return false;
  }
  this->Geometry = grid;
  this->InvSpacing = 1.0 / grid.Spacing;
  for (int a = 0; a < 3; ++a) this->Extent[a] = grid.Dimensions[a];
  this->MaterialList = materials;
  for (int a = 0; a < 3; ++a) this->BlockDims[a] = (grid.Dimensions[a] + BlockEdge - 1) / BlockEdge;
  this->BlockTable.assign(size_t(this->BlockDims[0]) * this->BlockDims[1] * this->BlockDims[2], -1);
  this->BlockCoordinates.clear();
  this->ProtectedBlocks.clear();
  this->MaterialCodes.clear();
  this->BuildDensities.clear();
  this->Finished = false;
  return true;
}

int32_t DrillVolume::Allocate(int bi, int bj, int bk) {
  int32_t& entry = this->BlockTable[(size_t(bk) * this->BlockDims[1] + bj) * this->BlockDims[0] + bi];
  if (entry >= 0) return entry;
  entry = static_cast<int32_t>(this->BlockCoordinates.size());
  this->BlockCoordinates.push_back({bi, bj, bk});
  this->ProtectedBlocks.push_back(0);
  this->MaterialCodes.resize(this->MaterialCodes.size() + BlockVoxels, 0);
  this->BuildDensities.resize(this->BuildDensities.size() + BlockVoxels, 0);
  return entry;
}

void DrillVolume::SetVoxel(int i, int j, int k, uint8_t density, uint8_t material, bool isProtected) {
  if (this->Finished || !this->Contains(i, j, k)) return;
  if (density == 0 && !isProtected && this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift) < 0) return;
  const int32_t s = this->Allocate(i >> BlockShift, j >> BlockShift, k >> BlockShift);
  const size_t v = size_t(s) * BlockVoxels + Local(i, j, k);
  this->BuildDensities[v] = density;
  this->MaterialCodes[v] = static_cast<uint8_t>((material & MaterialMask) | (isProtected ? ProtectedBit : 0));
  if (isProtected) this->ProtectedBlocks[size_t(s)] = 1;
}

void DrillVolume::Finish() {
  if (this->Finished) return;
  // A contour cell belongs to the block of its lowest corner and reads one voxel beyond it: the
  // blocks just below (in i, j, k and their combinations) a stored block must exist too.
  const size_t stored = this->BlockCoordinates.size();
  for (size_t s = 0; s < stored; ++s) {
    const auto c = this->BlockCoordinates[s];
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) {
          const int bi = c[0] - dx, bj = c[1] - dy, bk = c[2] - dz;
          if (bi >= 0 && bj >= 0 && bk >= 0) this->Allocate(bi, bj, bk);
        }
  }
  const size_t n = this->BlockCoordinates.size() * BlockVoxels;
  this->Densities.reset(new std::atomic<uint8_t>[n]);
  for (size_t v = 0; v < n; ++v) this->Densities[v].store(this->BuildDensities[v], std::memory_order_relaxed);
  this->Originals = std::move(this->BuildDensities);
  this->BuildDensities = {};
  this->DirtyFlags.reset(new std::atomic<uint8_t>[this->BlockCoordinates.size()]);
  for (size_t s = 0; s < this->BlockCoordinates.size(); ++s) this->DirtyFlags[s].store(0, std::memory_order_relaxed);
  this->InitialVolumes = this->CurrentVolumes();
  this->Finished = true;
}

void DrillVolume::Protect(int i, int j, int k) {
  if (!this->Contains(i, j, k)) return;
  const int32_t s = this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift);
  if (s < 0) return;
  this->MaterialCodes[size_t(s) * BlockVoxels + Local(i, j, k)] |= ProtectedBit;
  this->ProtectedBlocks[size_t(s)] = 1;
}

uint8_t DrillVolume::OriginalDensity(int i, int j, int k) const noexcept {
  if (!this->Contains(i, j, k)) return 0;
  const int32_t s = this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift);
  return s < 0 ? 0 : this->Originals[size_t(s) * BlockVoxels + Local(i, j, k)];
}

size_t DrillVolume::MemoryBytes() const {
  const size_t blocks = this->BlockCoordinates.size();
  // densities + original + material per voxel; per block: coordinates, flags; the block table.
  return blocks * (3 * size_t(BlockVoxels) + sizeof(std::array<int32_t, 3>) + 2) + this->BlockTable.size() * sizeof(int32_t);
}

std::vector<double> DrillVolume::CurrentVolumes() const {
  std::vector<double> volumes(this->MaterialList.size(), 0.0);
  if (!this->Densities) return volumes;
  for (size_t s = 0; s < this->BlockCoordinates.size(); ++s)
    for (int v = 0; v < BlockVoxels; ++v) {
      const size_t index = s * BlockVoxels + size_t(v);
      const int m = this->MaterialCodes[index] & MaterialMask;
      if (m > 0) volumes[size_t(m - 1)] += this->Densities[index].load(std::memory_order_relaxed) / 255.0;
    }
  for (double& v : volumes) v *= this->VoxelVolume();
  return volumes;
}

void DrillVolume::BoneBounds(Vec3& lo, Vec3& hi) const {
  lo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  hi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t s = 0; s < this->BlockCoordinates.size(); ++s) {
    const auto c = this->BlockCoordinates[s];
    for (int v = 0; v < BlockVoxels; ++v) {
      const uint8_t d = this->Densities ? this->Densities[s * BlockVoxels + size_t(v)].load(std::memory_order_relaxed)
                                        : this->BuildDensities[s * BlockVoxels + size_t(v)];
      if (d == 0) continue;
      const Vec3 p = this->Geometry.Center(c[0] * BlockEdge + (v & 7), c[1] * BlockEdge + ((v >> 3) & 7),
                                           c[2] * BlockEdge + (v >> 6));
      lo = Min(lo, p);
      hi = Max(hi, p);
    }
  }
}

VoxelBox DrillVolume::Clip(VoxelBox box) const {
  for (int a = 0; a < 3; ++a) {
    box.Lo[a] = std::max(box.Lo[a], 0);
    box.Hi[a] = std::min(box.Hi[a], this->Geometry.Dimensions[a] - 1);
  }
  return box;
}

VoxelBox DrillVolume::BoxAround(const Vec3& lo, const Vec3& hi) const {
  VoxelBox box;
  const Vec3 a = this->Geometry.ToIndex(lo), b = this->Geometry.ToIndex(hi);
  for (int k = 0; k < 3; ++k) {
    // Clamp before converting: a far-away point must not overflow int.
    const double l = std::clamp(std::ceil(a[k]), -1.0, double(this->Geometry.Dimensions[k]));
    const double h = std::clamp(std::floor(b[k]), -1.0, double(this->Geometry.Dimensions[k]));
    box.Lo[k] = static_cast<int>(l);
    box.Hi[k] = static_cast<int>(h);
  }
  return this->Clip(box);
}

void DrillVolume::MarkSlot(int32_t slot) noexcept {
  if (this->DirtyFlags[size_t(slot)].exchange(1, std::memory_order_acq_rel) == 0 && !this->Dirty->TryPush(slot))
    this->DirtyOverflow.store(true, std::memory_order_release);
}

void DrillVolume::MarkDirty(const VoxelBox& changed) noexcept {
  if (changed.Empty()) return;
  // Cells with a corner in the box, and the cells whose corner gradients read it (±1 voxel).
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, (changed.Lo[a] - 2) >> BlockShift);
    hi[a] = std::min(this->BlockDims[a] - 1, (changed.Hi[a] + 1) >> BlockShift);
  }
  for (int bk = lo[2]; bk <= hi[2]; ++bk)
    for (int bj = lo[1]; bj <= hi[1]; ++bj)
      for (int bi = lo[0]; bi <= hi[0]; ++bi) {
        const int32_t s = this->Slot(bi, bj, bk);
        if (s >= 0) this->MarkSlot(s);
      }
}

void DrillVolume::MarkAllDirty() noexcept {
  for (size_t s = 0; s < this->BlockCoordinates.size(); ++s) this->MarkSlot(static_cast<int32_t>(s));
}

}  // namespace rp
