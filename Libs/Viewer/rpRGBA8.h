#pragma once
// RGBA8 words (little-endian: R in the low byte) mixed a whole pixel at a time: the four channels
// spread into the four 16-bit lanes of a 64-bit word, so one multiply weighs them all. Per lane
// (a · (256 − w) + b · w + 128) >> 8 stays below 2^16 (255 · 256 + 128), so no lane carries into
// the next. The slice compositor's layer blend and the picture resampling both mix this way.
#include <cstdint>

namespace rp::rgba8 {

inline std::uint64_t Spread(std::uint32_t rgba) {
  return (rgba & 0xFFull) | ((rgba & 0xFF00ull) << 8) | ((rgba & 0xFF0000ull) << 16) | ((rgba & 0xFF000000ull) << 24);
}

/// `a` and `b` (spread) mixed with weight `w` of 256 on `b`: the lanes of the result are 0…255.
inline std::uint64_t Mix(std::uint64_t a, std::uint64_t b, std::uint64_t w) {
  constexpr std::uint64_t Half = 0x0080008000800080ull, Lanes = 0x00FF00FF00FF00FFull;
  return ((a * (256 - w) + b * w + Half) >> 8) & Lanes;
}

/// The red, green and blue lanes back into a word; alpha 0.
inline std::uint32_t GatherRGB(std::uint64_t lanes) {
  return static_cast<std::uint32_t>((lanes & 0xFF) | ((lanes >> 8) & 0xFF00) | ((lanes >> 16) & 0xFF0000));
}

}  // namespace rp::rgba8
