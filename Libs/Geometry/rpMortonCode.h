#pragma once
// Morton (Z-order) codes: points sorted by them are near their neighbours in the order. The BVH
// sorts triangles by them; the trajectory proposal orders its candidates by them (each candidate
// warm-starts from the previous one's closest triangle).
#include <cstdint>

namespace rp {

/// The low 21 bits of `v` spread to every third bit of 63: interleave three of them (x, y << 1,
/// z << 2) into a Morton code.
inline uint64_t SpreadMortonBits(uint64_t v) noexcept {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace rp
