#pragma once
// A planned straight trajectory as geometry: from the entry to the target (RAS, mm), the depth
// of a point along it, its offset across it, and the angle between two directions. The one
// definition the virtual fixtures (axis guidance, depth stop), the navigation read-outs and the
// score of an execution measure against. Plain C++; every query is noexcept and allocation-free.
#include <cstddef>
#include <string>

#include "rpVec3.h"

namespace rp {

class TrajectoryAxis {
 public:
  TrajectoryAxis() = default;
  /// False with `error` when the entry and the target coincide or are not finite.
  static bool Make(const Vec3& entry, const Vec3& target, TrajectoryAxis& axis, std::string& error);

  const Vec3& Entry() const { return this->EntryPoint; }
  const Vec3& Target() const { return this->TargetPoint; }
  /// Unit vector from the entry towards the target.
  const Vec3& Direction() const { return this->Unit; }
  double Length() const { return this->Span; }

  /// Signed distance along the axis from the entry plane (0 at the entry, Length() at the target).
  double Depth(const Vec3& p) const noexcept { return Dot(p - this->EntryPoint, this->Unit); }
  /// The point of the (infinite) axis line at `depth`.
  Vec3 PointAt(double depth) const noexcept { return this->EntryPoint + this->Unit * depth; }
  /// The vector from the axis line to `p`, normal to the axis.
  Vec3 Offset(const Vec3& p) const noexcept { return p - this->PointAt(this->Depth(p)); }
  /// Distance from `p` to the axis line.
  double Distance(const Vec3& p) const noexcept { return Norm(this->Offset(p)); }

 private:
  Vec3 EntryPoint, TargetPoint, Unit;
  double Span = 0;
};

/// Angle (degrees, 0–180) between two directions; 0 when either is zero.
double AngleBetweenDegrees(const Vec3& a, const Vec3& b) noexcept;

/// Where the line through `point` along `direction` crosses the plane through `planePoint` with
/// normal `planeNormal`. False when the line is parallel to the plane.
bool LinePlaneIntersection(const Vec3& point, const Vec3& direction, const Vec3& planePoint, const Vec3& planeNormal,
                           Vec3& crossing) noexcept;

/// Least-squares line through points (the principal axis of their scatter): a point on it (the
/// centroid) and a unit direction, oriented from the first point towards the last. False for
/// fewer than two distinct points.
bool FitLine(const Vec3* points, size_t count, Vec3& centroid, Vec3& direction);

}  // namespace rp
