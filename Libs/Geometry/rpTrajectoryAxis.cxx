#include "rpTrajectoryAxis.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace rp {

bool TrajectoryAxis::Make(const Vec3& entry, const Vec3& target, TrajectoryAxis& axis, std::string& error) {
  if (!Finite(entry) || !Finite(target)) {
    error = "trajectory: the entry or the target is not a finite point";
    return false;
  }
  const double length = Norm(target - entry);
  if (!(length > 1e-9)) {
    error = "trajectory: the entry and the target are the same point (a trajectory of zero length)";
    return false;
  }
  axis.EntryPoint = entry;
  axis.TargetPoint = target;
  axis.Unit = (target - entry) / length;
  axis.Span = length;
  return true;
}

double AngleBetweenDegrees(const Vec3& a, const Vec3& b) noexcept {
  const double na = Norm(a), nb = Norm(b);
  if (!(na > 0) || !(nb > 0)) return 0;
  // atan2 of |a×b| and a·b: accurate at small angles, where acos of the dot product is not.
  return std::atan2(Norm(Cross(a, b)), Dot(a, b)) * 180.0 / M_PI;
}

bool LinePlaneIntersection(const Vec3& point, const Vec3& direction, const Vec3& planePoint, const Vec3& planeNormal,
                           Vec3& crossing) noexcept {
  const double along = Dot(direction, planeNormal);
  if (std::fabs(along) < 1e-12 * Norm(direction) * Norm(planeNormal)) return false;
  crossing = point + direction * (Dot(planePoint - point, planeNormal) / along);
  return true;
}

bool FitLine(const Vec3* points, size_t count, Vec3& centroid, Vec3& direction) {
  if (count < 2) return false;
  // Centre first (with a shift by the first point, so far-away coordinates keep their digits).
  const Vec3 origin = points[0];
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < count; ++i) {
    const Vec3 d = points[i] - origin;
    mean += Eigen::Vector3d(d.x, d.y, d.z);
  }
  mean /= static_cast<double>(count);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < count; ++i) {
    const Vec3 d = points[i] - origin;
    const Eigen::Vector3d c = Eigen::Vector3d(d.x, d.y, d.z) - mean;
    scatter += c * c.transpose();
  }
  if (!(scatter.trace() > 0)) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::Vector3d axis = solver.eigenvectors().col(2);  // largest eigenvalue last
  centroid = origin + Vec3{mean.x(), mean.y(), mean.z()};
  direction = Normalized(Vec3{axis.x(), axis.y(), axis.z()});
  if (Dot(direction, points[count - 1] - points[0]) < 0) direction = -direction;
  return true;
}

}  // namespace rp
