#include "rpPictureResample.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <vtkSMPTools.h>

namespace rp {

namespace {

// RGBA8 spread into four 16-bit lanes, so one 64-bit multiply weighs all four channels.
inline std::uint64_t Spread(std::uint32_t rgba) {
  return (rgba & 0xFFull) | ((rgba & 0xFF00ull) << 8) | ((rgba & 0xFF0000ull) << 16) | ((rgba & 0xFF000000ull) << 24);
}
inline std::uint32_t Gather(std::uint64_t lanes) {
  return static_cast<std::uint32_t>((lanes & 0xFF) | ((lanes >> 8) & 0xFF00) | ((lanes >> 16) & 0xFF0000));
}
constexpr std::uint32_t Opaque = 0xFF000000u;  // alpha 255, little-endian RGBA words
constexpr std::uint64_t Half = 0x0080008000800080ull;  // 128 in each lane: rounds the >> 8

// One axis of an axis-aligned map: for each target index, the two source indices and the weight
// (of 256) of the second; Inside false beyond half a pixel of the picture.
struct Taps {
  std::vector<int> First, Second;
  std::vector<std::uint32_t> Weight;
  std::vector<char> Inside;
  Taps(int count, double origin, double step, int size) : First(count), Second(count), Weight(count), Inside(count) {
    for (int k = 0; k < count; ++k) {
      const double x = origin + k * step;
      Inside[k] = x >= -0.5 && x <= size - 0.5;
      const double clamped = std::clamp(x, 0.0, double(size - 1));
      First[k] = static_cast<int>(clamped);
      Second[k] = std::min(First[k] + 1, size - 1);
      Weight[k] = static_cast<std::uint32_t>((clamped - First[k]) * 256.0 + 0.5);
    }
  }
};

// The usual case (the slice camera's axes are the plane's): weights per column and per row
// computed once, and the filter is separable. Each target row first mixes its two source rows
// (one pass over the source columns it uses, in 16-bit lanes), then each pixel mixes two of
// those: two reads and two 64-bit multiplies a pixel, where a 2×2 tap costs four and six.
void ResampleAxisAligned(const std::uint32_t* source, int width, int height, const PixelMap& map,
                         std::uint32_t* target, int targetWidth, int targetHeight) {
  const Taps columns(targetWidth, map.Origin[0], map.AlongI[0], width);
  const Taps rows(targetHeight, map.Origin[1], map.AlongJ[1], height);
  int firstColumn = width, lastColumn = -1;  // the source columns any target pixel reads
  for (int i = 0; i < targetWidth; ++i) {
    if (!columns.Inside[i]) continue;
    firstColumn = std::min(firstColumn, columns.First[i]);
    lastColumn = std::max(lastColumn, columns.Second[i]);
  }
  constexpr std::uint64_t Lanes = 0x00FF00FF00FF00FFull;
  vtkSMPTools::For(0, targetHeight, 32, [&](int firstRow, int endRow) {
    std::vector<std::uint64_t> mixed(static_cast<size_t>(width));  // one target row's source row, mixed
    for (int j = firstRow; j < endRow; ++j) {
      std::uint32_t* out = target + static_cast<std::int64_t>(j) * targetWidth;
      if (!rows.Inside[j] || lastColumn < 0) {
        std::fill(out, out + targetWidth, Opaque);
        continue;
      }
      const std::uint32_t* bottom = source + static_cast<std::int64_t>(rows.First[j]) * width;
      const std::uint32_t* top = source + static_cast<std::int64_t>(rows.Second[j]) * width;
      const std::uint64_t wy = rows.Weight[j];
      // Every lane stays below 2^16: 255·256 plus the rounding half.
      for (int k = firstColumn; k <= lastColumn; ++k) {
        mixed[static_cast<size_t>(k)] = ((Spread(bottom[k]) * (256 - wy) + Spread(top[k]) * wy + Half) >> 8) & Lanes;
      }
      for (int i = 0; i < targetWidth; ++i) {
        if (!columns.Inside[i]) {
          out[i] = Opaque;
          continue;
        }
        const std::uint64_t wx = columns.Weight[i];
        const std::uint64_t sum = mixed[static_cast<size_t>(columns.First[i])] * (256 - wx) +
                                  mixed[static_cast<size_t>(columns.Second[i])] * wx + Half;
        out[i] = Gather((sum >> 8) & Lanes) | Opaque;
      }
    }
  });
}

}  // namespace

void ResampleOpaqueRGBA(const unsigned char* source, int width, int height, const PixelMap& map, unsigned char* target,
                        int targetWidth, int targetHeight) {
  if (targetWidth <= 0 || targetHeight <= 0) return;
  if (!source || width <= 0 || height <= 0) {
    for (int k = 0; k < targetWidth * targetHeight; ++k) {
      target[4 * k] = target[4 * k + 1] = target[4 * k + 2] = 0;
      target[4 * k + 3] = 255;
    }
    return;
  }
  // Within 1e-9 pixel a pixel of axis-aligned: under a millionth of a pixel across any view.
  if (std::fabs(map.AlongI[1]) < 1e-9 && std::fabs(map.AlongJ[0]) < 1e-9) {
    ResampleAxisAligned(reinterpret_cast<const std::uint32_t*>(source), width, height, map,
                        reinterpret_cast<std::uint32_t*>(target), targetWidth, targetHeight);
    return;
  }
  const double uMax = width - 0.5, vMax = height - 0.5;
  vtkSMPTools::For(0, targetHeight, 16, [&](int firstRow, int endRow) {
    for (int j = firstRow; j < endRow; ++j) {
      unsigned char* out = target + 4 * static_cast<std::int64_t>(j) * targetWidth;
      double u = map.Origin[0] + j * map.AlongJ[0], v = map.Origin[1] + j * map.AlongJ[1];
      for (int i = 0; i < targetWidth; ++i, out += 4, u += map.AlongI[0], v += map.AlongI[1]) {
        out[3] = 255;
        if (!(u >= -0.5 && u <= uMax && v >= -0.5 && v <= vMax)) {
          out[0] = out[1] = out[2] = 0;
          continue;
        }
        // Within half a pixel of the edge the edge pixel's colour (clamp to edge).
        const double uc = std::clamp(u, 0.0, double(width - 1)), vc = std::clamp(v, 0.0, double(height - 1));
        const int x0 = static_cast<int>(uc), y0 = static_cast<int>(vc);
        const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
        // 8-bit weights: exact to well under one grey level.
        const std::uint32_t wx = static_cast<std::uint32_t>((uc - x0) * 256.0 + 0.5);
        const std::uint32_t wy = static_cast<std::uint32_t>((vc - y0) * 256.0 + 0.5);
        const unsigned char* p00 = source + 4 * (static_cast<std::int64_t>(y0) * width + x0);
        const unsigned char* p10 = source + 4 * (static_cast<std::int64_t>(y0) * width + x1);
        const unsigned char* p01 = source + 4 * (static_cast<std::int64_t>(y1) * width + x0);
        const unsigned char* p11 = source + 4 * (static_cast<std::int64_t>(y1) * width + x1);
        for (int c = 0; c < 3; ++c) {
          const std::uint32_t bottom = p00[c] * (256 - wx) + p10[c] * wx;
          const std::uint32_t top = p01[c] * (256 - wx) + p11[c] * wx;
          out[c] = static_cast<unsigned char>((bottom * (256 - wy) + top * wy + 32768) >> 16);
        }
      }
    }
  });
}

}  // namespace rp
