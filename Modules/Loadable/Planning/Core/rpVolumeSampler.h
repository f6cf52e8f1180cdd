#pragma once
// A voxel volume sampled in world RAS (plain C++, no VTK): trilinear values (CT numbers) and
// nearest voxels (labels). It reads the caller's voxels in place (any integer or float type) and
// maps RAS to voxel indices with the inverse of the volume's IJK-to-world matrix. Queries are
// const, thread-safe and never allocate.
#include <cstdint>
#include <string>

#include "rpVec3.h"

namespace rp {

enum class VoxelType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

class VolumeSampler {
 public:
  /// `voxels` (x fastest, one component) stay the caller's and must outlive the sampler.
  /// `ijkToWorld` is row-major 4x4. False with `error` for an empty grid or a singular matrix.
  bool Set(const void* voxels, VoxelType type, const int dimensions[3], const double ijkToWorld[16], std::string& error);
  bool Empty() const { return this->Voxels == nullptr; }

  /// Continuous voxel index of a world point.
  Vec3 ToIndex(const Vec3& ras) const noexcept;
  /// Within the box of the voxel centres (where trilinear sampling needs no extrapolation).
  bool Inside(const Vec3& ras) const noexcept;
  /// Trilinear value; outside the voxel-centre box the nearest border value is used and
  /// `inside` is false.
  double Trilinear(const Vec3& ras, bool* inside = nullptr) const noexcept;
  /// The voxel whose centre is nearest (labels); `outside` (default 0) beyond the grid.
  double Nearest(const Vec3& ras, double outside = 0) const noexcept;
  /// Trilinear interpolation of a 0/1 predicate of the 8 surrounding voxel values: the smooth
  /// indicator of a set of labels or of voxels above a threshold (0.5 is its boundary).
  template <class Predicate>
  double Indicator(const Vec3& ras, Predicate&& predicate) const noexcept;
  /// The voxel value at integer indices (clamped to the grid).
  double Value(int i, int j, int k) const noexcept;

  const int* Dimensions() const { return this->Dims; }
  /// Smallest voxel spacing (mm).
  double MinimumSpacing() const { return this->MinSpacing; }
  /// World box of the voxel centres (a point is Inside when in it, up to rounding).
  Vec3 BoundsLo() const { return this->Lo; }
  Vec3 BoundsHi() const { return this->Hi; }

 private:
  template <class T>
  double At(size_t offset) const noexcept {
    return static_cast<double>(static_cast<const T*>(this->Voxels)[offset]);
  }
  double AtOffset(size_t offset) const noexcept;
  // Corner indices and weights of a trilinear sample (clamped to the grid).
  void Corners(const Vec3& index, int c[3], double w[3], bool* inside) const noexcept;

  const void* Voxels = nullptr;
  VoxelType Type = VoxelType::Int16;
  int Dims[3] = {0, 0, 0};
  double WorldToIJK[12] = {0};  // the inverse's first three rows
  double MinSpacing = 1;
  Vec3 Lo, Hi;
};

template <class Predicate>
double VolumeSampler::Indicator(const Vec3& ras, Predicate&& predicate) const noexcept {
  int c[3];
  double w[3];
  this->Corners(this->ToIndex(ras), c, w, nullptr);
  double sum = 0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const double weight = (di ? w[0] : 1 - w[0]) * (dj ? w[1] : 1 - w[1]) * (dk ? w[2] : 1 - w[2]);
        if (weight > 0 && predicate(this->Value(c[0] + di, c[1] + dj, c[2] + dk))) sum += weight;
      }
  return sum;
}

}  // namespace rp
