#pragma once
// A 3-vector of doubles for real-time geometry (no VTK, no allocation, trivially copyable).
#include <cmath>

namespace rp {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double Dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double Norm2(const Vec3& v) { return Dot(v, v); }
inline double Norm(const Vec3& v) { return std::sqrt(Dot(v, v)); }
/// Unit vector; the zero vector stays zero.
inline Vec3 Normalized(const Vec3& v) {
  const double n = Norm(v);
  return n > 0 ? v / n : Vec3{};
}
// As std::fmin/fmax (a NaN operand gives the other), written out: GCC calls libm for those
// unless math is finite-only, and the BVH's build and queries call these in their inner loops.
inline double MinOf(double a, double b) { return (b < a || a != a) ? b : a; }
inline double MaxOf(double a, double b) { return (b > a || a != a) ? b : a; }
inline Vec3 Min(const Vec3& a, const Vec3& b) { return {MinOf(a.x, b.x), MinOf(a.y, b.y), MinOf(a.z, b.z)}; }
inline Vec3 Max(const Vec3& a, const Vec3& b) { return {MaxOf(a.x, b.x), MaxOf(a.y, b.y), MaxOf(a.z, b.z)}; }
inline bool Finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace rp
