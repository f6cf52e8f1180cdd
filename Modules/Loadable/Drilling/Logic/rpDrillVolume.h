#pragma once
// A drillable bone: a regular voxel grid (axis-aligned in RAS, isotropic 0.2–0.5 mm) stored in
// 8³-voxel blocks; blocks with no bone and no protected voxel are not stored, so a whole bone at
// 0.3 mm takes tens of megabytes. Per voxel:
//  - a density 0..255: how much of the voxel is bone. Across a surface it is a linear ramp two
//    voxels wide, ρ = clamp(0.5 − sd / 2h), sd the signed distance (mm, > 0 outside) of the voxel
//    centre: the 50 % iso-surface is the surface, a plane is reproduced exactly by any ramp voxel,
//    and the burr carves the same ramp around its sphere (partial volumes, no staircase);
//  - a material: 0 none, else 1 + index into Materials() (drillable tissues of the material
//    table); bit 7 marks a protected voxel (never removed; the burr stops when it reaches one).
// Threads: the servo thread is the only writer of densities (carving, undo, reset) and marks the
// blocks it changes dirty (flag + lock-free ring); the display thread reads densities with relaxed
// atomics and re-contours dirty blocks. Geometry, materials and original densities are immutable
// once Finish() ran. Nothing here allocates after Finish().
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rpMaterial.h"
#include "rpSpscRing.h"
#include "rpVec3.h"

namespace rp {

struct DrillGrid {
  Vec3 Origin;           // RAS (mm) of voxel (0,0,0)'s centre
  double Spacing = 0.3;  // mm, the same along R, A and S
  std::array<int, 3> Dimensions{{0, 0, 0}};

  Vec3 Center(int i, int j, int k) const { return this->Origin + Vec3{double(i), double(j), double(k)} * this->Spacing; }
  /// Continuous voxel coordinates of a RAS point.
  Vec3 ToIndex(const Vec3& ras) const { return (ras - this->Origin) / this->Spacing; }
  size_t VoxelCount() const { return size_t(this->Dimensions[0]) * this->Dimensions[1] * this->Dimensions[2]; }
};

/// An inclusive voxel-index box.
struct VoxelBox {
  int Lo[3] = {0, 0, 0}, Hi[3] = {-1, -1, -1};
  bool Empty() const { return this->Hi[0] < this->Lo[0] || this->Hi[1] < this->Lo[1] || this->Hi[2] < this->Lo[2]; }
};

class DrillVolume {
 public:
  static_assert(sizeof(std::atomic<uint8_t>) == 1, "densities are read as bytes");
  static constexpr int BlockEdge = 8;
  static constexpr int BlockShift = 3;
  static constexpr int BlockVoxels = BlockEdge * BlockEdge * BlockEdge;
  static constexpr uint8_t ProtectedBit = 0x80;
  static constexpr uint8_t MaterialMask = 0x7f;
  static constexpr int MaxMaterials = 16;
  using DirtyRing = SpscRing<int32_t, (1 << 16)>;

  /// Density of a voxel whose centre is `sd` mm outside a surface (negative: inside), spacing h.
  static double RampDensity(double sd, double spacing) {
    const double rho = 0.5 - sd / (2.0 * spacing);
    return rho < 0 ? 0.0 : (rho > 1 ? 1.0 : rho);
  }
  static uint8_t Quantize(double rho) { return static_cast<uint8_t>((rho < 0 ? 0 : rho > 1 ? 1 : rho) * 255.0 + 0.5); }

  DrillVolume();
  ~DrillVolume();
  DrillVolume(const DrillVolume&) = delete;
  DrillVolume& operator=(const DrillVolume&) = delete;

  // ---- building (one thread, before any servo/display thread uses the volume)
  /// Starts an empty volume. `materials` are the drillable tissues (voxel material m refers to
  /// materials[m − 1]); at most MaxMaterials. False names the problem.
  bool Initialize(const DrillGrid& grid, const std::vector<Material>& materials, std::string& error);
  /// Sets a voxel (allocating its block). `material` is 0 (none) or 1..Materials().size().
  void SetVoxel(int i, int j, int k, uint8_t density, uint8_t material, bool isProtected);
  /// Allocates the blocks needed to contour across block faces, freezes the layout, keeps the
  /// original densities (Reset) and counts the bone per material.
  void Finish();
  /// Marks a stored voxel protected (after Finish too, but before any servo or display thread
  /// uses the volume): structures at risk added from a plan (rpDrillProtection.h).
  void Protect(int i, int j, int k);

  // ---- reading (any thread)
  const DrillGrid& Grid() const { return this->Geometry; }
  double Spacing() const { return this->Geometry.Spacing; }
  double VoxelVolume() const { return this->Geometry.Spacing * this->Geometry.Spacing * this->Geometry.Spacing; }
  const std::vector<Material>& Materials() const { return this->MaterialList; }
  const std::array<int, 3>& BlockDimensions() const { return this->BlockDims; }
  size_t AllocatedBlocks() const { return this->BlockCoordinates.size(); }
  size_t MemoryBytes() const;
  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < this->Geometry.Dimensions[0] && j < this->Geometry.Dimensions[1] &&
           k < this->Geometry.Dimensions[2];
  }
  /// Block slot of block (bi, bj, bk), −1 when not stored (all empty).
  int32_t Slot(int bi, int bj, int bk) const noexcept {
    if (bi < 0 || bj < 0 || bk < 0 || bi >= this->BlockDims[0] || bj >= this->BlockDims[1] || bk >= this->BlockDims[2])
      return -1;
    return this->BlockTable[(size_t(bk) * this->BlockDims[1] + bj) * this->BlockDims[0] + bi];
  }
  static int Local(int i, int j, int k) noexcept {
    return (i & (BlockEdge - 1)) | ((j & (BlockEdge - 1)) << BlockShift) | ((k & (BlockEdge - 1)) << (2 * BlockShift));
  }
  uint8_t Density(int i, int j, int k) const noexcept {
    if (!this->Contains(i, j, k)) return 0;
    const int32_t s = this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift);
    return s < 0 ? 0 : this->Densities[size_t(s) * BlockVoxels + Local(i, j, k)].load(std::memory_order_relaxed);
  }
  uint8_t MaterialCode(int i, int j, int k) const noexcept {
    if (!this->Contains(i, j, k)) return 0;
    const int32_t s = this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift);
    return s < 0 ? 0 : this->MaterialCodes[size_t(s) * BlockVoxels + Local(i, j, k)];
  }
  uint8_t OriginalDensity(int i, int j, int k) const noexcept;
  /// Trilinearly interpolated density (0–1) at a RAS point; `code` gets the material code of the
  /// densest of the 8 voxels around it (0 when all are empty). One block lookup when the 8 voxels
  /// share a block (7 cells in 8 along each axis). Never allocates. The servo thread's (the
  /// writer's) or, with no servo running, any one thread's: it reads densities without atomics.
  double Sample(const Vec3& ras, uint8_t& code) const noexcept { return this->Interpolate<true>(ras, &code); }
  /// The same density without the material (cheaper: the sweep only needs where the bone is).
  double Sample(const Vec3& ras) const noexcept { return this->Interpolate<false>(ras, nullptr); }
  /// Bone volume (mm³) per material index (0-based) as built, and now.
  const std::vector<double>& OriginalVolumes() const { return this->InitialVolumes; }
  std::vector<double> CurrentVolumes() const;  // scans every block (not for the servo thread)
  /// Every voxel the burr took material from: its centre and the volume taken (mm³), for scoring
  /// the execution against its plan. Scans every block (not for the servo thread).
  template <typename F>
  void ForEachRemoved(F&& f) const;
  /// RAS bounds of the stored bone (voxel centres with density > 0).
  void BoneBounds(Vec3& lo, Vec3& hi) const;

  // ---- block access for the cutter (servo thread) and the mesher (display thread)
  const std::array<int32_t, 3>& BlockCoordinate(int32_t slot) const { return this->BlockCoordinates[size_t(slot)]; }
  std::atomic<uint8_t>* BlockDensities(int32_t slot) noexcept { return &this->Densities[size_t(slot) * BlockVoxels]; }
  const std::atomic<uint8_t>* BlockDensities(int32_t slot) const noexcept {
    return &this->Densities[size_t(slot) * BlockVoxels];
  }
  const uint8_t* BlockMaterials(int32_t slot) const noexcept { return &this->MaterialCodes[size_t(slot) * BlockVoxels]; }
  const uint8_t* BlockOriginal(int32_t slot) const noexcept { return &this->Originals[size_t(slot) * BlockVoxels]; }
  bool BlockHasProtected(int32_t slot) const noexcept { return this->ProtectedBlocks[size_t(slot)] != 0; }
  /// Clamps a box to the grid.
  VoxelBox Clip(VoxelBox box) const;
  /// The voxel box of a RAS axis-aligned box (voxel centres inside), clipped to the grid.
  VoxelBox BoxAround(const Vec3& lo, const Vec3& hi) const;

  /// Calls f(slot, lo, hi) for every stored block overlapping `box` (clipped to the grid), with
  /// lo/hi the inclusive global voxel range of the overlap. Never allocates.
  template <typename F>
  void ForEachBlock(const VoxelBox& box, F&& f) const;

  /// Calls f(slot, local, count, w) for each run of stored voxels along a row (`count` voxels
  /// i, i+1, … of one block; `local` the first's local index, w = v − c its centre's offset, the
  /// next one's is w + (h, 0, 0)) whose centres v lie in the spherical shell rIn <= |v − c| <= rOut
  /// (rIn 0: the whole ball) and, when `keep` is given, in its half space. The row's ranges are
  /// computed once per row, never a test per voxel outside them. `clipLo`/`clipHi` (RAS) limit
  /// the rows to a box. Never allocates.
  struct HalfSpace {
    Vec3 Normal;    // unit
    double Offset = 0;  // keeps v with Dot(v − c, Normal) >= Offset
  };
  /// Every Period-th row: rows (j, k) with (j + 2k) mod Period = Phase (a lattice that spreads
  /// each share over the whole shell).
  struct RowSlice {
    int Period = 1, Phase = 0;
  };
  template <typename F>
  void ForEachRunInShell(const Vec3& c, double rIn, double rOut, const HalfSpace* keep, const Vec3& clipLo,
                         const Vec3& clipHi, const RowSlice& rows, F&& f) const;

  // ---- dirty blocks: servo thread marks, display thread takes
  /// Marks the blocks whose contour cells (and their normals) depend on voxels in `changed`.
  void MarkDirty(const VoxelBox& changed) noexcept;
  void MarkAllDirty() noexcept;
  /// Display thread: calls f(slot) for each dirty block (and clears its flag before f reads it).
  template <typename F>
  size_t TakeDirty(F&& f);

 private:
  void MarkSlot(int32_t slot) noexcept;
  int32_t Allocate(int bi, int bj, int bk);
  template <bool WithCode>
  double Interpolate(const Vec3& ras, uint8_t* code) const noexcept;
  template <bool WithCode>
  double InterpolateAcrossBlocks(int i, int j, int k, double u, double v, double w, uint8_t* code) const noexcept;

  DrillGrid Geometry;
  double InvSpacing = 1.0 / 0.3;
  double Extent[3] = {0, 0, 0};  // the dimensions as doubles (Sample's bounds test)
  std::vector<Material> MaterialList;
  std::array<int, 3> BlockDims{{0, 0, 0}};
  std::vector<int32_t> BlockTable;
  std::vector<std::array<int32_t, 3>> BlockCoordinates;
  std::vector<uint8_t> ProtectedBlocks;
  std::vector<uint8_t> MaterialCodes;
  std::vector<uint8_t> BuildDensities;  // while building
  std::vector<uint8_t> Originals;
  std::unique_ptr<std::atomic<uint8_t>[]> Densities;
  std::unique_ptr<std::atomic<uint8_t>[]> DirtyFlags;
  std::unique_ptr<DirtyRing> Dirty;
  std::atomic<bool> DirtyOverflow{false};
  std::vector<double> InitialVolumes;
  bool Finished = false;
};

template <typename F>
void DrillVolume::ForEachRemoved(F&& f) const {
  if (!this->Densities) return;
  const double unit = this->VoxelVolume() / 255.0;
  for (size_t s = 0; s < this->BlockCoordinates.size(); ++s) {
    const auto& c = this->BlockCoordinates[s];
    for (int v = 0; v < BlockVoxels; ++v) {
      const size_t index = s * BlockVoxels + size_t(v);
      const int now = this->Densities[index].load(std::memory_order_relaxed), before = this->Originals[index];
      if (now >= before) continue;
      f(this->Geometry.Center(c[0] * BlockEdge + (v & (BlockEdge - 1)), c[1] * BlockEdge + ((v >> BlockShift) & (BlockEdge - 1)),
                              c[2] * BlockEdge + (v >> (2 * BlockShift))),
        (before - now) * unit);
    }
  }
}

namespace drill_detail {
/// Trilinear interpolation of 8 corner densities (x fastest), scaled to 0–1.
inline double Trilinear(const uint8_t d[8], double u, double v, double w) noexcept {
  const double x00 = d[0] + (d[1] - d[0]) * u, x10 = d[2] + (d[3] - d[2]) * u;
  const double x01 = d[4] + (d[5] - d[4]) * u, x11 = d[6] + (d[7] - d[6]) * u;
  const double y0 = x00 + (x10 - x00) * v, y1 = x01 + (x11 - x01) * v;
  return (y0 + (y1 - y0) * w) * (1.0 / 255.0);
}
inline int Densest(const uint8_t d[8]) noexcept {
  int densest = 0;
  for (int c = 1; c < 8; ++c)
    if (d[c] > d[densest]) densest = c;
  return densest;
}
}  // namespace drill_detail

template <bool WithCode>
inline double DrillVolume::Interpolate(const Vec3& ras, uint8_t* code) const noexcept {
  const double inv = this->InvSpacing;
  const double x = (ras.x - this->Geometry.Origin.x) * inv, y = (ras.y - this->Geometry.Origin.y) * inv,
               z = (ras.z - this->Geometry.Origin.z) * inv;
  if constexpr (WithCode) *code = 0;
  if (!(x >= -1 && y >= -1 && z >= -1 && x < this->Extent[0] && y < this->Extent[1] && z < this->Extent[2]))
    return 0;  // outside the grid (NaN too)
  // floor() of values >= −1 without a library call.
  const int i = static_cast<int>(x + 1.0) - 1, j = static_cast<int>(y + 1.0) - 1, k = static_cast<int>(z + 1.0) - 1;
  const int li = i & (BlockEdge - 1), lj = j & (BlockEdge - 1), lk = k & (BlockEdge - 1);
  if (li == BlockEdge - 1 || lj == BlockEdge - 1 || lk == BlockEdge - 1)
    return this->InterpolateAcrossBlocks<WithCode>(i, j, k, x - i, y - j, z - k, code);
  // 7 cells in 8 along each axis: the 8 voxels share one block (in the grid: i, j, k >= 0), at
  // fixed offsets. Plain byte reads (unsigned char may read any object): Sample runs on the servo
  // thread, the densities' only writer, so this is no data race; unlike atomic loads they let
  // the compiler keep the geometry in registers.
  const int32_t s = this->BlockTable[(size_t(k >> BlockShift) * this->BlockDims[1] + (j >> BlockShift)) * this->BlockDims[0] +
                                     (i >> BlockShift)];
  if (s < 0) return 0;
  const size_t base = size_t(s) * BlockVoxels + size_t(li | (lj << BlockShift) | (lk << (2 * BlockShift)));
  const uint8_t* p = reinterpret_cast<const uint8_t*>(this->Densities.get()) + base;
  constexpr int E = BlockEdge, EE = BlockEdge * BlockEdge;
  constexpr int offset[8] = {0, 1, E, E + 1, EE, EE + 1, EE + E, EE + E + 1};
  const uint8_t d[8] = {p[offset[0]], p[offset[1]], p[offset[2]], p[offset[3]],
                        p[offset[4]], p[offset[5]], p[offset[6]], p[offset[7]]};
  if constexpr (WithCode) {
    const int densest = drill_detail::Densest(d);
    if (d[densest] > 0) *code = this->MaterialCodes[base + size_t(offset[densest])];
  }
  return drill_detail::Trilinear(d, x - i, y - j, z - k);
}

template <bool WithCode>
double DrillVolume::InterpolateAcrossBlocks(int i, int j, int k, double u, double v, double w, uint8_t* code) const noexcept {
  // The blocks the corners fall in (2, 4 or 8; a block beyond the grid or not stored is empty),
  // each looked up once; then each corner's block and local index from two choices per axis.
  const int ex = (i & (BlockEdge - 1)) == BlockEdge - 1, ey = (j & (BlockEdge - 1)) == BlockEdge - 1,
            ez = (k & (BlockEdge - 1)) == BlockEdge - 1;
  const int bi = i >> BlockShift, bj = j >> BlockShift, bk = k >> BlockShift;
  const int mask = ex | (ey << 1) | (ez << 2);
  int32_t blocks[8];
  for (int b = 0; b < 8; ++b)
    if ((b & mask) == b) blocks[b] = this->Slot(bi + (b & 1), bj + ((b >> 1) & 1), bk + (b >> 2));
  const int l[3][2] = {{i & (BlockEdge - 1), (i + 1) & (BlockEdge - 1)},
                       {(j & (BlockEdge - 1)) << BlockShift, ((j + 1) & (BlockEdge - 1)) << BlockShift},
                       {(k & (BlockEdge - 1)) << (2 * BlockShift), ((k + 1) & (BlockEdge - 1)) << (2 * BlockShift)}};
  const uint8_t* densities = reinterpret_cast<const uint8_t*>(this->Densities.get());  // see Interpolate
  uint8_t d[8];
  int64_t where[8];  // slot * BlockVoxels + local, −1 none
  for (int c = 0; c < 8; ++c) {
    const int32_t slot = blocks[c & mask];
    where[c] = slot < 0 ? -1 : int64_t(slot) * BlockVoxels + (l[0][c & 1] | l[1][(c >> 1) & 1] | l[2][c >> 2]);
    d[c] = slot < 0 ? uint8_t(0) : densities[where[c]];
  }
  if constexpr (WithCode) {
    const int densest = drill_detail::Densest(d);
    if (d[densest] > 0) *code = this->MaterialCodes[size_t(where[densest])];
  }
  return drill_detail::Trilinear(d, u, v, w);
}

template <typename F>
void DrillVolume::ForEachBlock(const VoxelBox& region, F&& f) const {
  const VoxelBox box = this->Clip(region);
  if (box.Empty()) return;
  int blo[3], bhi[3];
  for (int a = 0; a < 3; ++a) {
    blo[a] = box.Lo[a] >> BlockShift;
    bhi[a] = box.Hi[a] >> BlockShift;
  }
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi) {
        const int32_t s = this->Slot(bi, bj, bk);
        if (s < 0) continue;
        const int b[3] = {bi, bj, bk};
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::max(box.Lo[a], b[a] << BlockShift);
          hi[a] = std::min(box.Hi[a], (b[a] << BlockShift) + BlockEdge - 1);
        }
        f(s, lo, hi);
      }
}

template <typename F>
void DrillVolume::ForEachRunInShell(const Vec3& c, double rIn, double rOut, const HalfSpace* keep, const Vec3& clipLo,
                                    const Vec3& clipHi, const RowSlice& rows, F&& f) const {
  if (!(rOut > 0)) return;
  const double h = this->Geometry.Spacing, inv = this->InvSpacing;
  const Vec3& o = this->Geometry.Origin;
  const double out2 = rOut * rOut, in2 = rIn > 0 ? rIn * rIn : -1.0;
  const Vec3 reach{rOut, rOut, rOut};
  const VoxelBox box = this->BoxAround(Max(c - reach, clipLo), Min(c + reach, clipHi));
  if (box.Empty()) return;
  // The least index at or above, the greatest at or below a coordinate x, clamped to
  // [−1, Hi + 1] before converting (a far bound must not overflow int); floor as a truncation of
  // a non-negative value (no libm call: these run a few times per row).
  const double top = box.Hi[0] + 1.0;
  const auto atMost = [&](double x) { return static_cast<int>(std::clamp((x - o.x) * inv, -1.0, top) + 1.0) - 1; };
  const auto atLeast = [&](double x) {
    const double t = std::clamp((x - o.x) * inv, -1.0, top);
    const int f = static_cast<int>(t + 1.0) - 1;
    return f + (f < t);
  };
  // A segment [a, b] of row (j, k), split at block edges; blocks not stored are skipped.
  const auto walk = [&](int a, int b, int j, int k, double dy, double dz) {
    const int rowLocal = Local(0, j, k);
    for (int i = a; i <= b;) {
      const int blockLast = std::min(b, i | (BlockEdge - 1));
      const int32_t slot = this->Slot(i >> BlockShift, j >> BlockShift, k >> BlockShift);
      if (slot >= 0) f(slot, rowLocal | (i & (BlockEdge - 1)), blockLast - i + 1, Vec3{o.x + i * h - c.x, dy, dz});
      i = blockLast + 1;
    }
  };
  for (int k = box.Lo[2]; k <= box.Hi[2]; ++k) {
    const double dz = o.z + k * h - c.z;
    const int period = std::max(1, rows.Period);
    const int firstJ = box.Lo[1] + ((rows.Phase - box.Lo[1] - 2 * k) % period + period) % period;
    for (int j = firstJ; j <= box.Hi[1]; j += period) {
      const double dy = o.y + j * h - c.y;
      const double row2 = dy * dy + dz * dz;
      if (row2 > out2) continue;
      const double half = std::sqrt(out2 - row2);
      int first = std::max(box.Lo[0], atLeast(c.x - half)), last = std::min(box.Hi[0], atMost(c.x + half));
      if (keep) {  // n·(v − c) >= offset is a bound on i (or all or nothing when n ⟂ the row)
        const Vec3& n = keep->Normal;
        const double rest = keep->Offset - n.y * dy - n.z * dz;
        if (n.x > 1e-12)
          first = std::max(first, atLeast(c.x + rest / n.x));
        else if (n.x < -1e-12)
          last = std::min(last, atMost(c.x + rest / n.x));
        else if (rest > 0)
          continue;
      }
      if (first > last) continue;
      if (row2 < in2) {  // the part inside the inner sphere is left out
        const double inner = std::sqrt(in2 - row2);
        const int skipFirst = atMost(c.x - inner) + 1, skipLast = atLeast(c.x + inner) - 1;
        if (skipFirst <= skipLast) {
          walk(first, std::min(last, skipFirst - 1), j, k, dy, dz);
          walk(std::max(first, skipLast + 1), last, j, k, dy, dz);
          continue;
        }
      }
      walk(first, last, j, k, dy, dz);
    }
  }
}

template <typename F>
size_t DrillVolume::TakeDirty(F&& f) {
  size_t n = 0;
  if (this->DirtyOverflow.exchange(false, std::memory_order_acq_rel)) {
    // The ring overflowed: scan every flag (drop what the ring still holds; the flags decide).
    int32_t ignored;
    while (this->Dirty->TryPop(ignored)) {
    }
    for (size_t s = 0; s < this->BlockCoordinates.size(); ++s)
      if (this->DirtyFlags[s].exchange(0, std::memory_order_acq_rel)) {
        f(static_cast<int32_t>(s));
        ++n;
      }
    return n;
  }
  int32_t slot;
  while (this->Dirty->TryPop(slot)) {
    // acq_rel: synchronizes with the servo's marking, so f sees the densities it wrote.
    if (!this->DirtyFlags[size_t(slot)].exchange(0, std::memory_order_acq_rel)) continue;
    f(slot);
    ++n;
  }
  return n;
}

}  // namespace rp
