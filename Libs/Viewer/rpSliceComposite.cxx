#include "rpSliceComposite.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <cstring>
#include <type_traits>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkTemplateAliasMacro.h>

#include "rpParallelFor.h"
#include "rpRGBA8.h"

namespace rp {

namespace {

// The picture is walked in tiles of Band rows × Chunk pixels: a tile's voxels stay in cache for
// its neighbouring rows whatever the plane's orientation (a row of a sagittal picture steps
// across the CT's rows, so row after row re-reads lines a whole row has evicted).
constexpr int Chunk = 32;  // pixels sampled per layer at a time (stack buffers)
constexpr int Band = 16;

std::atomic<bool> UseAVX2{true};  // SetCompositeVectorized (tests, benchmarks)

struct Sampled {
  float Values[Chunk];
  std::uint8_t Inside[Chunk];
};

// The voxel grid of a layer, in indices relative to its extent's first corner.
struct Grid {
  int Size[3];
  explicit Grid(const SliceLayer& layer) {
    for (int a = 0; a < 3; ++a) Size[a] = layer.Extent[2 * a + 1] - layer.Extent[2 * a] + 1;
  }
  // Within half a voxel of the edge voxels' centres (vtkImageReslice's border).
  bool Contains(const double p[3]) const {
    for (int a = 0; a < 3; ++a) {
      if (!(p[a] >= -0.5 && p[a] <= Size[a] - 0.5)) return false;
    }
    return true;
  }
};

inline float Lerp(float a, float b, float t) { return a + t * (b - a); }

// A row's samples lie at p(k) = start + k · step (always computed so, whatever path takes them).
struct Row {
  const double* Start;
  const double* Step;
  double At(int a, int k) const { return this->Start[a] + k * this->Step[a]; }
};

// Samples k0 … k1 − 1 of a row, any of them (near the edges or outside too): trilinear, or the
// nearest voxel for labels; Inside is 0 where a pixel lies outside the volume.
template <typename T, bool Nearest>
void SampleAny(const SliceLayer& layer, const Grid& grid, Row row, int k0, int k1, Sampled& out) {
  const T* base = static_cast<const T*>(layer.Scalars);
  for (int k = k0; k < k1; ++k) {
    const double p[3] = {row.At(0, k), row.At(1, k), row.At(2, k)};
    out.Inside[k] = grid.Contains(p);
    if (!out.Inside[k]) continue;
    if constexpr (Nearest) {
      vtkIdType offset = 0;
      for (int a = 0; a < 3; ++a) {
        // p ≥ −0.5 (inside): truncation is the floor; p = size − 0.5 rounds to size.
        offset += std::min(static_cast<int>(p[a] + 0.5), grid.Size[a] - 1) * layer.Increments[a];
      }
      out.Values[k] = static_cast<float>(base[offset]);
    } else {
      int index[3];
      float f[3];
      vtkIdType next[3];
      for (int a = 0; a < 3; ++a) {
        const double c = std::clamp(p[a], 0.0, double(grid.Size[a] - 1));
        index[a] = static_cast<int>(c);
        f[a] = static_cast<float>(c - index[a]);
        next[a] = index[a] + 1 < grid.Size[a] ? layer.Increments[a] : 0;
      }
      const T* q = base + index[0] * layer.Increments[0] + index[1] * layer.Increments[1] + index[2] * layer.Increments[2];
      const float c00 = Lerp(float(q[0]), float(q[next[0]]), f[0]);
      const float c10 = Lerp(float(q[next[1]]), float(q[next[1] + next[0]]), f[0]);
      const float c01 = Lerp(float(q[next[2]]), float(q[next[2] + next[0]]), f[0]);
      const float c11 = Lerp(float(q[next[2] + next[1]]), float(q[next[2] + next[1] + next[0]]), f[0]);
      out.Values[k] = Lerp(Lerp(c00, c10, f[1]), Lerp(c01, c11, f[1]), f[2]);
    }
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// SampleInterior for 16-bit volumes (CT, MR), eight samples at a time with AVX2's gathers: the
// same operations in the same order (doubles for the positions, floats for the weights and the
// lerps, no fused multiply-add), so the same values bit for bit. Returns the first sample it
// left (fewer than eight at the end, or a group whose last corner is the volume's last voxel: a
// 32-bit gather there would read past it).
#define RP_AVX2 __attribute__((target("avx2"), always_inline)) inline
// p = start + k · step for samples k … k + 7: their voxel index (truncated) and fraction.
RP_AVX2 void Positions8(double start, double step, int k, __m256i& index, __m256& fraction) {
  const __m256d s = _mm256_set1_pd(start), d = _mm256_set1_pd(step);
  const __m256d p0 = _mm256_add_pd(s, _mm256_mul_pd(_mm256_set_pd(k + 3, k + 2, k + 1, k), d));
  const __m256d p1 = _mm256_add_pd(s, _mm256_mul_pd(_mm256_set_pd(k + 7, k + 6, k + 5, k + 4), d));
  const __m128i i0 = _mm256_cvttpd_epi32(p0), i1 = _mm256_cvttpd_epi32(p1);
  const __m128 f0 = _mm256_cvtpd_ps(_mm256_sub_pd(p0, _mm256_cvtepi32_pd(i0)));
  const __m128 f1 = _mm256_cvtpd_ps(_mm256_sub_pd(p1, _mm256_cvtepi32_pd(i1)));
  index = _mm256_setr_m128i(i0, i1);
  fraction = _mm256_setr_m128(f0, f1);
}
// Eight 16-bit voxels at byte offsets from `bytes`, as floats.
template <bool Signed>
RP_AVX2 __m256 Load8(const int* bytes, __m256i byteOffsets) {
  const __m256i low = _mm256_slli_epi32(_mm256_i32gather_epi32(bytes, byteOffsets, 1), 16);
  return _mm256_cvtepi32_ps(Signed ? _mm256_srai_epi32(low, 16) : _mm256_srli_epi32(low, 16));
}
RP_AVX2 __m256 Lerp8(__m256 a, __m256 b, __m256 t) { return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a))); }

template <bool Signed>
__attribute__((target("avx2"))) int SampleInterior16AVX2(const SliceLayer& layer, const Grid& grid, Row row, int k0,
                                                          int k1, Sampled& out) {
  const vtkIdType di = layer.Increments[0], dj = layer.Increments[1], dk = layer.Increments[2];
  const vtkIdType last = (grid.Size[0] - 1) * di + (grid.Size[1] - 1) * dj + (grid.Size[2] - 1) * dk;
  if (2 * (last + 1) > 0x7FFFFFFF) return k0;  // byte offsets must fit 32 bits
  const auto* bytes = static_cast<const int*>(layer.Scalars);
  // A sample whose first corner is this voxel or beyond has the volume's last voxel as a corner.
  const __m256i unsafe = _mm256_set1_epi32(static_cast<int>(last - di - dj - dk));
  const __m256i ci = _mm256_set1_epi32(static_cast<int>(2 * di)), cj = _mm256_set1_epi32(static_cast<int>(2 * dj)),
                ck = _mm256_set1_epi32(static_cast<int>(2 * dk));
  const __m256i cij = _mm256_add_epi32(ci, cj), cik = _mm256_add_epi32(ci, ck), cjk = _mm256_add_epi32(cj, ck),
                cijk = _mm256_add_epi32(cij, ck);
  const __m256i ei = _mm256_set1_epi32(static_cast<int>(di)), ej = _mm256_set1_epi32(static_cast<int>(dj)),
                ek = _mm256_set1_epi32(static_cast<int>(dk));
  int k = k0;
  for (; k + 8 <= k1; k += 8) {
    __m256i i, j, l;
    __m256 fx, fy, fz;
    Positions8(row.Start[0], row.Step[0], k, i, fx);
    Positions8(row.Start[1], row.Step[1], k, j, fy);
    Positions8(row.Start[2], row.Step[2], k, l, fz);
    const __m256i voxel = _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(i, ei), _mm256_mullo_epi32(j, ej)),
                                           _mm256_mullo_epi32(l, ek));
    const __m256i atOrPast = _mm256_cmpgt_epi32(_mm256_add_epi32(voxel, _mm256_set1_epi32(1)), unsafe);
    if (!_mm256_testz_si256(atOrPast, atOrPast)) break;
    const __m256i q = _mm256_add_epi32(voxel, voxel);  // bytes
    const __m256 c00 = Lerp8(Load8<Signed>(bytes, q), Load8<Signed>(bytes, _mm256_add_epi32(q, ci)), fx);
    const __m256 c10 = Lerp8(Load8<Signed>(bytes, _mm256_add_epi32(q, cj)), Load8<Signed>(bytes, _mm256_add_epi32(q, cij)), fx);
    const __m256 c01 = Lerp8(Load8<Signed>(bytes, _mm256_add_epi32(q, ck)), Load8<Signed>(bytes, _mm256_add_epi32(q, cik)), fx);
    const __m256 c11 = Lerp8(Load8<Signed>(bytes, _mm256_add_epi32(q, cjk)), Load8<Signed>(bytes, _mm256_add_epi32(q, cijk)), fx);
    _mm256_storeu_ps(out.Values + k, Lerp8(Lerp8(c00, c10, fy), Lerp8(c01, c11, fy), fz));
  }
  return k;
}
#undef RP_AVX2

bool HasAVX2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

// Samples whose 2 × 2 × 2 voxels all lie in the grid (most of a picture): SampleAny's arithmetic
// without its clamps and tests, so the same values. A row that steps along the volume's fastest
// axis alone (an axis-aligned plane on its layout copy) keeps its other two coordinates: those are
// worked out once.
template <typename T>
void SampleInterior(const SliceLayer& layer, const Grid& grid, Row row, int k0, int k1, Sampled& out) {
  const T* base = static_cast<const T*>(layer.Scalars);
  const vtkIdType di = layer.Increments[0], dj = layer.Increments[1], dk = layer.Increments[2];
  std::fill(out.Inside + k0, out.Inside + k1, std::uint8_t{1});
#if defined(__x86_64__) && defined(__GNUC__)
  if constexpr (std::is_same_v<T, short> || std::is_same_v<T, unsigned short>) {
    if (UseAVX2.load(std::memory_order_relaxed) && HasAVX2()) k0 = SampleInterior16AVX2<std::is_same_v<T, short>>(layer, grid, row, k0, k1, out);
  }
#else
  (void)grid;
#endif
  if (row.Step[1] == 0 && row.Step[2] == 0) {
    const int j = static_cast<int>(row.Start[1]), l = static_cast<int>(row.Start[2]);
    const float fy = static_cast<float>(row.Start[1] - j), fz = static_cast<float>(row.Start[2] - l);
    const T* line = base + j * dj + l * dk;
    for (int k = k0; k < k1; ++k) {
      const double x = row.At(0, k);
      const int i = static_cast<int>(x);
      const float fx = static_cast<float>(x - i);
      const T* q = line + i * di;
      const float c00 = Lerp(float(q[0]), float(q[di]), fx);
      const float c10 = Lerp(float(q[dj]), float(q[dj + di]), fx);
      const float c01 = Lerp(float(q[dk]), float(q[dk + di]), fx);
      const float c11 = Lerp(float(q[dk + dj]), float(q[dk + dj + di]), fx);
      out.Values[k] = Lerp(Lerp(c00, c10, fy), Lerp(c01, c11, fy), fz);
    }
    return;
  }
  for (int k = k0; k < k1; ++k) {
    const double x = row.At(0, k), y = row.At(1, k), z = row.At(2, k);
    const int i = static_cast<int>(x), j = static_cast<int>(y), l = static_cast<int>(z);
    const float fx = static_cast<float>(x - i), fy = static_cast<float>(y - j), fz = static_cast<float>(z - l);
    const T* q = base + i * di + j * dj + l * dk;
    const float c00 = Lerp(float(q[0]), float(q[di]), fx);
    const float c10 = Lerp(float(q[dj]), float(q[dj + di]), fx);
    const float c01 = Lerp(float(q[dk]), float(q[dk + di]), fx);
    const float c11 = Lerp(float(q[dk + dj]), float(q[dk + dj + di]), fx);
    out.Values[k] = Lerp(Lerp(c00, c10, fy), Lerp(c01, c11, fy), fz);
  }
}

// Labels within half a voxel of the grid: the nearest voxel without the test.
template <typename T>
void SampleNearestInside(const SliceLayer& layer, const Grid& grid, Row row, int k0, int k1, Sampled& out) {
  const T* base = static_cast<const T*>(layer.Scalars);
  std::fill(out.Inside + k0, out.Inside + k1, std::uint8_t{1});
  for (int k = k0; k < k1; ++k) {
    vtkIdType offset = 0;
    for (int a = 0; a < 3; ++a) {
      offset += std::min(static_cast<int>(row.At(a, k) + 0.5), grid.Size[a] - 1) * layer.Increments[a];
    }
    out.Values[k] = static_cast<float>(base[offset]);
  }
}

// The samples of a row that the fast paths may take: trilinear, those with all 2 × 2 × 2 voxels
// in the grid (p in [0, size − 1) on every axis); nearest, those within half a voxel of it. Each
// axis's p(k) is monotone in k, so these samples are one run [first, end): estimated from the
// line, then moved until its two ends pass the test itself.
struct FastRun {
  int First = 0, End = 0;
};
FastRun FindFastRun(const Grid& grid, bool nearest, Row row, int n) {
  auto fast = [&](int k) {
    for (int a = 0; a < 3; ++a) {
      const double p = row.At(a, k);
      if (nearest ? !(p >= -0.5 && p <= grid.Size[a] - 0.5) : !(p >= 0 && p < grid.Size[a] - 1)) return false;
    }
    return true;
  };
  double lo = 0, hi = n - 1;
  for (int a = 0; a < 3; ++a) {
    const double low = nearest ? -0.5 : 0.0, high = nearest ? grid.Size[a] - 0.5 : grid.Size[a] - 1.0;
    const double s = row.Start[a], d = row.Step[a];
    if (d == 0) {
      if (!(s >= low && s <= high)) return {};
      continue;
    }
    const double k0 = (low - s) / d, k1 = (high - s) / d;
    lo = std::max(lo, std::min(k0, k1));
    hi = std::min(hi, std::max(k0, k1));
  }
  if (!(lo <= hi)) return {};
  FastRun run{static_cast<int>(std::clamp(std::ceil(lo), 0.0, double(n))), 0};
  run.End = std::max(run.First, static_cast<int>(std::clamp(std::floor(hi) + 1, 0.0, double(n))));
  // The estimate is within a sample or two of the exact ends; step in (or out) until it matches.
  while (run.First > 0 && fast(run.First - 1)) --run.First;
  while (run.First < run.End && !fast(run.First)) ++run.First;
  while (run.End < n && run.End > run.First && fast(run.End)) ++run.End;
  while (run.End > run.First && !fast(run.End - 1)) --run.End;
  return run;
}

template <typename T>
void SampleTyped(const SliceLayer& layer, const double start[3], const double step[3], int n, Sampled& out) {
  const Grid grid(layer);
  const Row row{start, step};
  const FastRun run = FindFastRun(grid, layer.Nearest, row, n);
  auto any = [&](int k0, int k1) {
    if (k0 >= k1) return;
    if (layer.Nearest) SampleAny<T, true>(layer, grid, row, k0, k1, out);
    else SampleAny<T, false>(layer, grid, row, k0, k1, out);
  };
  any(0, run.First);
  if (layer.Nearest) SampleNearestInside<T>(layer, grid, row, run.First, run.End, out);
  else SampleInterior<T>(layer, grid, row, run.First, run.End, out);
  any(run.End, n);
}

void Sample(const SliceLayer& layer, const double start[3], const double step[3], int n, Sampled& out) {
  switch (layer.ScalarType) {
    vtkTemplateAliasMacro(SampleTyped<VTK_TT>(layer, start, step, n, out));
    default:
      std::fill(out.Inside, out.Inside + n, std::uint8_t{0});
  }
}

inline std::uint32_t Lookup(const SliceLayer& layer, float value) {
  const double position = (value - layer.TableMin) * layer.TableScale;
  // NaN and below the table → the first entry, as vtkLookupTable clamps.
  const int entry = position >= 0 ? static_cast<int>(std::min(position, double(layer.TableSize - 1))) : 0;
  return layer.Table[entry];
}

// `over` drawn on `under` with `weight` of 256 (its alpha times the layer's opacity); the alpha
// stays `under`'s.
inline std::uint32_t Blend(std::uint32_t under, std::uint32_t over, std::uint32_t weight) {
  return (under & 0xFF000000u) | rgba8::GatherRGB(rgba8::Mix(rgba8::Spread(under), rgba8::Spread(over), weight));
}

// The first component of every voxel, from `in` (increments `from`) to `out` with `axis` fastest.
template <int Bytes>
void CopyWithAxisFastest(const unsigned char* in, const vtkIdType from[3], const int size[3], int axis,
                         unsigned char* out, vtkIdType to[3]) {
  const int a = axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
  to[a] = 1;
  to[b] = size[a];
  to[c] = static_cast<vtkIdType>(size[a]) * size[b];
  ParallelFor(0, size[c], [&](int first, int end) {
    for (int z = first; z < end; ++z)
      for (int y = 0; y < size[b]; ++y) {
        const unsigned char* source = in + Bytes * (z * from[c] + y * from[b]);
        unsigned char* target = out + Bytes * (z * to[c] + y * to[b]);
        for (int x = 0; x < size[a]; ++x) std::memcpy(target + Bytes * x, source + Bytes * x * from[a], Bytes);
      }
  });
}

}  // namespace

SliceLayer SliceLayerOf(vtkImageData* image, const double planeToIJK[3][4], const double origin[2], double spacing) {
  SliceLayer layer;
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars) return layer;
  image->GetExtent(layer.Extent);
  layer.Scalars = scalars->GetVoidPointer(0);
  layer.ScalarType = scalars->GetDataType();
  layer.Increments[0] = scalars->GetNumberOfComponents();
  layer.Increments[1] = layer.Increments[0] * (layer.Extent[1] - layer.Extent[0] + 1);
  layer.Increments[2] = layer.Increments[1] * (layer.Extent[3] - layer.Extent[2] + 1);
  // Pixel (x, y) is at plane point (origin + spacing · (x, y), 0).
  for (int a = 0; a < 3; ++a) {
    const double* m = planeToIJK[a];
    layer.PixelToIJK[a][0] = m[0] * spacing;
    layer.PixelToIJK[a][1] = m[1] * spacing;
    layer.PixelToIJK[a][2] = m[0] * origin[0] + m[1] * origin[1] + m[3];
  }
  return layer;
}

void SetCompositeVectorized(bool vectorized) { UseAVX2.store(vectorized, std::memory_order_relaxed); }

bool OpaqueExtent(const std::uint32_t* picture, int width, int height, int extent[4]) {
  int x0 = width, x1 = -1, y0 = height, y1 = -1;
  for (int y = 0; y < height; ++y) {
    const std::uint32_t* row = picture + static_cast<std::int64_t>(y) * width;
    int first = 0;
    while (first < width && !(row[first] >> 24)) ++first;
    if (first == width) continue;
    int last = width - 1;
    while (!(row[last] >> 24)) --last;
    x0 = std::min(x0, first);
    x1 = std::max(x1, last);
    y0 = std::min(y0, y);
    y1 = y;
  }
  if (x1 < 0) return false;
  extent[0] = x0;
  extent[1] = x1;
  extent[2] = y0;
  extent[3] = y1;
  return true;
}

void SliceLayoutCache::Apply(vtkImageData* image, SliceLayer& layer) {
  // The axis the rows step along most; i is the volume's own fastest.
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::fabs(layer.PixelToIJK[a][0]) > std::fabs(layer.PixelToIJK[axis][0])) axis = a;
  }
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  const int bytes = scalars ? scalars->GetDataTypeSize() : 0;
  if (axis == 0 || !scalars || (bytes != 1 && bytes != 2 && bytes != 4 && bytes != 8)) return;
  int size[3];
  for (int a = 0; a < 3; ++a) size[a] = layer.Extent[2 * a + 1] - layer.Extent[2 * a] + 1;
  const vtkMTimeType time = image->GetMTime();
  Copy* copy = nullptr;
  for (Copy& c : this->Copies) {
    if (c.Image == image && c.Axis == axis) copy = &c;
  }
  if (!copy) {
    this->Copies.emplace_back();
    copy = &this->Copies.back();
    copy->Image = image;
    copy->Axis = axis;
  }
  const size_t voxels = static_cast<size_t>(size[0]) * size[1] * size[2];
  if (copy->Time != time || copy->Bytes.size() != voxels * bytes) {
    copy->Bytes.resize(voxels * bytes);
    const auto* in = static_cast<const unsigned char*>(layer.Scalars);
    switch (bytes) {
      case 1: CopyWithAxisFastest<1>(in, layer.Increments, size, axis, copy->Bytes.data(), copy->Increments); break;
      case 2: CopyWithAxisFastest<2>(in, layer.Increments, size, axis, copy->Bytes.data(), copy->Increments); break;
      case 4: CopyWithAxisFastest<4>(in, layer.Increments, size, axis, copy->Bytes.data(), copy->Increments); break;
      default: CopyWithAxisFastest<8>(in, layer.Increments, size, axis, copy->Bytes.data(), copy->Increments); break;
    }
    copy->Time = time;
  }
  layer.Scalars = copy->Bytes.data();
  std::copy(copy->Increments, copy->Increments + 3, layer.Increments);
}

void SliceLayoutCache::Keep(const std::vector<const vtkImageData*>& images) {
  this->Copies.erase(std::remove_if(this->Copies.begin(), this->Copies.end(),
                                    [&](const Copy& c) { return std::find(images.begin(), images.end(), c.Image) == images.end(); }),
                     this->Copies.end());
}

void CompositeSlice(const SliceLayer* layers, int count, int width, int height, std::uint32_t* picture,
                    bool parallel) {
  if (width <= 0 || height <= 0) return;
  const int bands = (height + Band - 1) / Band;
  auto composite = [&](int firstBand, int endBand) {
    Sampled sampled;
    for (int x0 = 0; x0 < width; x0 += Chunk)
      for (int y = firstBand * Band; y < std::min(height, endBand * Band); ++y) {
        std::uint32_t* row = picture + static_cast<std::int64_t>(y) * width;
        const int n = std::min(Chunk, width - x0);
        std::fill(row + x0, row + x0 + n, 0u);
        for (int l = 0; l < count; ++l) {
          const SliceLayer& layer = layers[l];
          if (!layer.Scalars || !layer.Table || layer.TableSize <= 0) continue;
          const double(&m)[3][3] = layer.PixelToIJK;
          double start[3], step[3];
          for (int a = 0; a < 3; ++a) {
            start[a] = m[a][0] * x0 + m[a][1] * y + m[a][2] - layer.Extent[2 * a];
            step[a] = m[a][0];
          }
          Sample(layer, start, step, n, sampled);
          std::uint32_t* out = row + x0;
          if (l == 0) {
            for (int k = 0; k < n; ++k) out[k] = sampled.Inside[k] ? Lookup(layer, sampled.Values[k]) : 0u;
            continue;
          }
          const double opacity = std::clamp(layer.Opacity, 0.0, 1.0) * 256.0 / 255.0;
          for (int k = 0; k < n; ++k) {
            if (!sampled.Inside[k]) continue;
            const std::uint32_t color = Lookup(layer, sampled.Values[k]);
            const auto weight = static_cast<std::uint32_t>((color >> 24) * opacity + 0.5);
            if (weight) out[k] = Blend(out[k], color, std::min<std::uint32_t>(weight, 256));
          }
        }
      }
  };
  if (parallel) {
    ParallelFor(0, bands, 1, composite);
  } else {
    composite(0, bands);
  }
}

}  // namespace rp
