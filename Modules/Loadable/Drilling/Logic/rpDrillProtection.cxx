#include "rpDrillProtection.h"

#include <algorithm>
#include <cmath>

namespace rp {

size_t ProtectRegions(DrillVolume& bone, const std::vector<ProtectedRegion>& regions) {
  const DrillGrid& grid = bone.Grid();
  const int E = DrillVolume::BlockEdge;
  const double h = grid.Spacing, half = 0.5 * E * h * std::sqrt(3.0);
  size_t marked = 0;
  for (const ProtectedRegion& r : regions) {
    if (!r.Surface || r.Surface->Empty()) continue;
    const double reach = r.MarginMm - 2 * h;  // the protected shell's outer distance
    for (size_t s = 0; s < bone.AllocatedBlocks(); ++s) {
      const auto c = bone.BlockCoordinate(int32_t(s));
      const Vec3 centre = grid.Center(c[0] * E, c[1] * E, c[2] * E) + Vec3{1, 1, 1} * (0.5 * (E - 1) * h);
      const double d = r.Surface->SignedDistance(centre);
      if (d - half > reach) continue;       // every voxel of the block is farther (|∇d| = 1)
      const bool whole = d + half <= reach;  // every voxel is within
      for (int v = 0; v < DrillVolume::BlockVoxels; ++v) {
        const int i = c[0] * E + (v & (E - 1)), j = c[1] * E + ((v >> 3) & (E - 1)), k = c[2] * E + (v >> 6);
        if (bone.OriginalDensity(i, j, k) == 0 || (bone.MaterialCode(i, j, k) & DrillVolume::ProtectedBit)) continue;
        if (!whole && r.Surface->SignedDistance(grid.Center(i, j, k)) > reach) continue;
        bone.Protect(i, j, k);
        ++marked;
      }
    }
  }
  return marked;
}

}  // namespace rp
