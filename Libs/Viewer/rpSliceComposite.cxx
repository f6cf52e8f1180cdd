#include "rpSliceComposite.h"

#include <algorithm>
#include <cmath>

#include <cstring>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkTemplateAliasMacro.h>

namespace rp {

namespace {

// The picture is walked in tiles of Band rows × Chunk pixels: a tile's voxels stay in cache for
// its neighbouring rows whatever the plane's orientation (a row of a sagittal picture steps
// across the CT's rows, so row after row re-reads lines a whole row has evicted).
constexpr int Chunk = 32;  // pixels sampled per layer at a time (stack buffers)
constexpr int Band = 16;

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

// Trilinear (or nearest for labels) samples of a row of pixels, in Values; Inside is 0 where a
// pixel lies outside the volume.
template <typename T, bool Nearest>
void SampleRow(const SliceLayer& layer, const double start[3], const double step[3], int n, Sampled& out) {
  const T* base = static_cast<const T*>(layer.Scalars);
  const Grid grid(layer);
  for (int k = 0; k < n; ++k) {
    const double p[3] = {start[0] + k * step[0], start[1] + k * step[1], start[2] + k * step[2]};
    out.Inside[k] = grid.Contains(p);
    if (!out.Inside[k]) continue;
    if constexpr (Nearest) {
      vtkIdType offset = 0;
      for (int a = 0; a < 3; ++a) {
        offset += std::clamp(static_cast<int>(std::floor(p[a] + 0.5)), 0, grid.Size[a] - 1) * layer.Increments[a];
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
      auto lerp = [](float a, float b, float t) { return a + t * (b - a); };
      const float c00 = lerp(float(q[0]), float(q[next[0]]), f[0]);
      const float c10 = lerp(float(q[next[1]]), float(q[next[1] + next[0]]), f[0]);
      const float c01 = lerp(float(q[next[2]]), float(q[next[2] + next[0]]), f[0]);
      const float c11 = lerp(float(q[next[2] + next[1]]), float(q[next[2] + next[1] + next[0]]), f[0]);
      out.Values[k] = lerp(lerp(c00, c10, f[1]), lerp(c01, c11, f[1]), f[2]);
    }
  }
}

template <typename T>
void SampleTyped(const SliceLayer& layer, const double start[3], const double step[3], int n, Sampled& out) {
  if (layer.Nearest) SampleRow<T, true>(layer, start, step, n, out);
  else SampleRow<T, false>(layer, start, step, n, out);
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
  std::uint32_t result = under & 0xFF000000u;
  for (int shift = 0; shift < 24; shift += 8) {
    const std::uint32_t a = (under >> shift) & 0xFF, b = (over >> shift) & 0xFF;
    result |= ((a * (256 - weight) + b * weight + 128) >> 8) << shift;
  }
  return result;
}

// The first component of every voxel, from `in` (increments `from`) to `out` with `axis` fastest.
template <int Bytes>
void CopyWithAxisFastest(const unsigned char* in, const vtkIdType from[3], const int size[3], int axis,
                         unsigned char* out, vtkIdType to[3]) {
  const int a = axis, b = (axis + 1) % 3, c = (axis + 2) % 3;
  to[a] = 1;
  to[b] = size[a];
  to[c] = static_cast<vtkIdType>(size[a]) * size[b];
  vtkSMPTools::For(0, size[c], [&](int first, int end) {
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
    vtkSMPTools::For(0, bands, 1, composite);
  } else {
    composite(0, bands);
  }
}

}  // namespace rp
