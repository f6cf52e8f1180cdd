#include "rpPictureResample.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <vtkSMPTools.h>

#include "rpRGBA8.h"

namespace rp {

namespace {

constexpr std::uint32_t Opaque = 0xFF000000u;  // alpha 255, little-endian RGBA words

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

// Each target row first mixes its two source rows, then each pixel two of those: in 16-bit lanes
// (a channel each), (a · (256 − w) + b · w + 128) >> 8, which stays below 2^16. With SSE2 (every
// x86-64) two pixels at a time, without it one in a 64-bit word; both give the same bits.
#if defined(__SSE2__)
// Source row pixels [first, last] of `bottom` and `top` mixed with weight wy (of 256).
void MixRows(const std::uint32_t* bottom, const std::uint32_t* top, std::uint32_t wy, int first, int last,
             std::uint64_t* mixed) {
  const __m128i zero = _mm_setzero_si128(), half = _mm_set1_epi16(128);
  const __m128i wb = _mm_set1_epi16(static_cast<short>(256 - wy)), wt = _mm_set1_epi16(static_cast<short>(wy));
  int k = first;
  for (; k + 1 <= last; k += 2) {  // two pixels: 8 channels
    const __m128i b = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(bottom + k)), zero);
    const __m128i t = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(top + k)), zero);
    const __m128i sum = _mm_add_epi16(_mm_add_epi16(_mm_mullo_epi16(b, wb), _mm_mullo_epi16(t, wt)), half);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(mixed + k), _mm_srli_epi16(sum, 8));
  }
  for (; k <= last; ++k) {
    const __m128i b = _mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(bottom[k])), zero);
    const __m128i t = _mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(top[k])), zero);
    const __m128i sum = _mm_add_epi16(_mm_add_epi16(_mm_mullo_epi16(b, wb), _mm_mullo_epi16(t, wt)), half);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(mixed + k), _mm_srli_epi16(sum, 8));
  }
}

// Target pixels [first, end) of a row from the mixed source row; alpha made opaque.
void MixColumns(const std::uint64_t* mixed, const int* firstTap, const int* secondTap, const std::uint64_t* weights,
                int first, int end, std::uint32_t* out) {
  const __m128i half = _mm_set1_epi16(128), opaque = _mm_set1_epi32(static_cast<int>(Opaque));
  int i = first;
  for (; i + 2 <= end; i += 2) {
    const __m128i a = _mm_set_epi64x(static_cast<long long>(mixed[firstTap[i + 1]]), static_cast<long long>(mixed[firstTap[i]]));
    const __m128i b = _mm_set_epi64x(static_cast<long long>(mixed[secondTap[i + 1]]), static_cast<long long>(mixed[secondTap[i]]));
    // weights[2i] = 256 − w and weights[2i + 1] = w in every lane.
    const __m128i w0 = _mm_set_epi64x(static_cast<long long>(weights[2 * i + 2]), static_cast<long long>(weights[2 * i]));
    const __m128i w1 = _mm_set_epi64x(static_cast<long long>(weights[2 * i + 3]), static_cast<long long>(weights[2 * i + 1]));
    const __m128i sum = _mm_srli_epi16(_mm_add_epi16(_mm_add_epi16(_mm_mullo_epi16(a, w0), _mm_mullo_epi16(b, w1)), half), 8);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_or_si128(_mm_packus_epi16(sum, sum), opaque));
  }
  for (; i < end; ++i) {
    const __m128i a = _mm_cvtsi64_si128(static_cast<long long>(mixed[firstTap[i]]));
    const __m128i b = _mm_cvtsi64_si128(static_cast<long long>(mixed[secondTap[i]]));
    const __m128i w0 = _mm_cvtsi64_si128(static_cast<long long>(weights[2 * i]));
    const __m128i w1 = _mm_cvtsi64_si128(static_cast<long long>(weights[2 * i + 1]));
    const __m128i sum = _mm_srli_epi16(_mm_add_epi16(_mm_add_epi16(_mm_mullo_epi16(a, w0), _mm_mullo_epi16(b, w1)), half), 8);
    out[i] = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(sum, sum))) | Opaque;
  }
}
#else
void MixRows(const std::uint32_t* bottom, const std::uint32_t* top, std::uint32_t wy, int first, int last,
             std::uint64_t* mixed) {
  for (int k = first; k <= last; ++k) mixed[k] = rgba8::Mix(rgba8::Spread(bottom[k]), rgba8::Spread(top[k]), wy);
}

void MixColumns(const std::uint64_t* mixed, const int* firstTap, const int* secondTap, const std::uint64_t* weights,
                int first, int end, std::uint32_t* out) {
  for (int i = first; i < end; ++i) {
    // Lane 0 of weights[2i + 1] is the weight w.
    out[i] = rgba8::GatherRGB(rgba8::Mix(mixed[firstTap[i]], mixed[secondTap[i]], weights[2 * i + 1] & 0xFFFF)) | Opaque;
  }
}
#endif

// The usual case (the slice camera's axes are the plane's): weights per column and per row
// computed once, and the filter is separable: two reads a pixel where a 2 × 2 tap costs four.
void ResampleAxisAligned(const std::uint32_t* source, int width, int height, const PixelMap& map,
                         std::uint32_t* target, int targetWidth, int targetHeight) {
  const Taps columns(targetWidth, map.Origin[0], map.AlongI[0], width);
  const Taps rows(targetHeight, map.Origin[1], map.AlongJ[1], height);
  // The target columns within the picture are one run (the map is monotone along a row).
  int firstInside = targetWidth, endInside = 0;
  for (int i = 0; i < targetWidth; ++i) {
    if (!columns.Inside[i]) continue;
    firstInside = std::min(firstInside, i);
    endInside = i + 1;
  }
  int firstColumn = width, lastColumn = -1;  // the source columns those read
  for (int i = firstInside; i < endInside; ++i) {
    firstColumn = std::min({firstColumn, columns.First[i], columns.Second[i]});
    lastColumn = std::max({lastColumn, columns.First[i], columns.Second[i]});
  }
  // Per target column, 256 − w and w repeated in four 16-bit lanes.
  std::vector<std::uint64_t> weights(2 * static_cast<size_t>(targetWidth));
  for (int i = 0; i < targetWidth; ++i) {
    weights[2 * static_cast<size_t>(i)] = (256 - columns.Weight[i]) * 0x0001000100010001ull;
    weights[2 * static_cast<size_t>(i) + 1] = columns.Weight[i] * 0x0001000100010001ull;
  }
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
      MixRows(bottom, top, rows.Weight[j], firstColumn, lastColumn, mixed.data());
      std::fill(out, out + firstInside, Opaque);
      MixColumns(mixed.data(), columns.First.data(), columns.Second.data(), weights.data(), firstInside, endInside, out);
      std::fill(out + std::max(firstInside, endInside), out + targetWidth, Opaque);
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
