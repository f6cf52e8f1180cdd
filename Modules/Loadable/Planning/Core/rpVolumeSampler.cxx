#include "rpVolumeSampler.h"

#include <algorithm>
#include <cmath>

namespace rp {

bool VolumeSampler::Set(const void* voxels, VoxelType type, const int dimensions[3], const double m[16],
                        std::string& error) {
  if (!voxels || dimensions[0] < 1 || dimensions[1] < 1 || dimensions[2] < 1) {
    error = "the volume has no voxels";
    return false;
  }
  // Inverse of the 3x3 part (adjugate / determinant) and of the translation.
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], k = m[10];
  const double det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g);
  if (!(std::fabs(det) > 1e-12) || !std::isfinite(det)) {
    error = "the volume's IJK-to-RAS matrix is singular";
    return false;
  }
  const double inv[9] = {(e * k - f * h) / det, (c * h - b * k) / det, (b * f - c * e) / det,
                         (f * g - d * k) / det, (a * k - c * g) / det, (c * d - a * f) / det,
                         (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col) this->WorldToIJK[4 * r + col] = inv[3 * r + col];
    this->WorldToIJK[4 * r + 3] = -(inv[3 * r] * m[3] + inv[3 * r + 1] * m[7] + inv[3 * r + 2] * m[11]);
  }
  this->MinSpacing = HUGE_VAL;
  for (int col = 0; col < 3; ++col)
    this->MinSpacing = std::min(this->MinSpacing, std::sqrt(m[col] * m[col] + m[4 + col] * m[4 + col] + m[8 + col] * m[8 + col]));
  this->Lo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  this->Hi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const double ijk[3] = {corner & 1 ? dimensions[0] - 1.0 : 0.0, corner & 2 ? dimensions[1] - 1.0 : 0.0,
                           corner & 4 ? dimensions[2] - 1.0 : 0.0};
    Vec3 p;
    for (int r = 0; r < 3; ++r) p[r] = m[4 * r] * ijk[0] + m[4 * r + 1] * ijk[1] + m[4 * r + 2] * ijk[2] + m[4 * r + 3];
    this->Lo = Min(this->Lo, p);
    this->Hi = Max(this->Hi, p);
  }
  this->Voxels = voxels;
  this->Type = type;
  std::copy(dimensions, dimensions + 3, this->Dims);
  return true;
}

Vec3 VolumeSampler::ToIndex(const Vec3& p) const noexcept {
  const double* m = this->WorldToIJK;
  return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
          m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

bool VolumeSampler::Inside(const Vec3& ras) const noexcept {
  const Vec3 index = this->ToIndex(ras);
  constexpr double slack = 1e-9;
  for (int i = 0; i < 3; ++i)
    if (!(index[i] >= -slack && index[i] <= this->Dims[i] - 1 + slack)) return false;
  return true;
}

double VolumeSampler::AtOffset(size_t offset) const noexcept {
  switch (this->Type) {
    case VoxelType::Int8: return this->At<int8_t>(offset);
    case VoxelType::UInt8: return this->At<uint8_t>(offset);
    case VoxelType::Int16: return this->At<int16_t>(offset);
    case VoxelType::UInt16: return this->At<uint16_t>(offset);
    case VoxelType::Int32: return this->At<int32_t>(offset);
    case VoxelType::UInt32: return this->At<uint32_t>(offset);
    case VoxelType::Int64: return this->At<int64_t>(offset);
    case VoxelType::UInt64: return this->At<uint64_t>(offset);
    case VoxelType::Float32: return this->At<float>(offset);
    case VoxelType::Float64: return this->At<double>(offset);
  }
  return 0;
}

double VolumeSampler::Value(int i, int j, int k) const noexcept {
  i = std::clamp(i, 0, this->Dims[0] - 1);
  j = std::clamp(j, 0, this->Dims[1] - 1);
  k = std::clamp(k, 0, this->Dims[2] - 1);
  return this->AtOffset(static_cast<size_t>(i) + static_cast<size_t>(this->Dims[0]) *
                                                     (static_cast<size_t>(j) + static_cast<size_t>(this->Dims[1]) * k));
}

void VolumeSampler::Corners(const Vec3& index, int c[3], double w[3], bool* inside) const noexcept {
  bool in = true;
  for (int a = 0; a < 3; ++a) {
    const double top = this->Dims[a] - 1.0;
    double x = index[a];
    if (!(x >= 0 && x <= top)) {  // also NaN
      in = in && std::fabs(x - std::clamp(x, 0.0, top)) < 1e-9;
      x = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, top);
    }
    c[a] = std::min(static_cast<int>(std::floor(x)), std::max(0, this->Dims[a] - 2));
    w[a] = this->Dims[a] > 1 ? x - c[a] : 0.0;
  }
  if (inside) *inside = in;
}

double VolumeSampler::Trilinear(const Vec3& ras, bool* inside) const noexcept {
  int c[3];
  double w[3];
  this->Corners(this->ToIndex(ras), c, w, inside);
  double sum = 0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const double weight = (di ? w[0] : 1 - w[0]) * (dj ? w[1] : 1 - w[1]) * (dk ? w[2] : 1 - w[2]);
        if (weight > 0) sum += weight * this->Value(c[0] + di, c[1] + dj, c[2] + dk);
      }
  return sum;
}

double VolumeSampler::Nearest(const Vec3& ras, double outside) const noexcept {
  const Vec3 index = this->ToIndex(ras);
  int ijk[3];
  for (int a = 0; a < 3; ++a) {
    const double r = std::round(index[a]);
    if (!(r >= 0 && r <= this->Dims[a] - 1)) return outside;
    ijk[a] = static_cast<int>(r);
  }
  return this->Value(ijk[0], ijk[1], ijk[2]);
}

}  // namespace rp
