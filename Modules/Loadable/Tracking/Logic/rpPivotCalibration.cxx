#include "rpPivotCalibration.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace rp {

namespace {
Eigen::Matrix3d Rotation(const ToolPose& p) {
  return Eigen::Quaterniond(p.Quaternion[0], p.Quaternion[1], p.Quaternion[2], p.Quaternion[3]).normalized().toRotationMatrix();
}
}  // namespace

PivotResult PivotCalibrate(const std::vector<ToolPose>& poses, double thresholdMm, double minSpreadDeg) {
  PivotResult result;
  std::vector<const ToolPose*> used;
  for (const ToolPose& p : poses)
    if (p.State == ToolState::OK) used.push_back(&p);
  result.PosesUsed = used.size();
  if (used.size() < 6) {
    result.Message = "pivot calibration needs at least 6 valid poses, got " + std::to_string(used.size());
    return result;
  }
  // Spread of orientations: angle of each pose from the (sign-aligned) mean quaternion.
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  const Eigen::Vector4d first(used[0]->Quaternion[0], used[0]->Quaternion[1], used[0]->Quaternion[2], used[0]->Quaternion[3]);
  for (const ToolPose* p : used) {
    Eigen::Vector4d q(p->Quaternion[0], p->Quaternion[1], p->Quaternion[2], p->Quaternion[3]);
    mean += q.dot(first) < 0 ? -q : q;
  }
  mean.normalize();
  for (const ToolPose* p : used) {
    const Eigen::Vector4d q(p->Quaternion[0], p->Quaternion[1], p->Quaternion[2], p->Quaternion[3]);
    const double angle = 2 * std::acos(std::min(1.0, std::abs(q.dot(mean)))) * 180.0 / M_PI;
    result.RotationSpreadDeg = std::max(result.RotationSpreadDeg, angle);
  }
  if (result.RotationSpreadDeg < minSpreadDeg) {
    result.Message = "the stylus did not rotate enough about its tip (" + std::to_string(result.RotationSpreadDeg) +
                     " deg, need " + std::to_string(minSpreadDeg) + ")";
    return result;
  }
  // [R_i  -I] [tip; pivot] = -t_i
  const Eigen::Index n = static_cast<Eigen::Index>(used.size());
  Eigen::MatrixXd A(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    A.block<3, 3>(3 * i, 0) = Rotation(*used[static_cast<size_t>(i)]);
    A.block<3, 3>(3 * i, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * i) = -Eigen::Vector3d(used[static_cast<size_t>(i)]->Translation);
  }
  const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d r = A.block<3, 6>(3 * i, 0) * x - b.segment<3>(3 * i);
    sum += r.squaredNorm();
    result.MaxError = std::max(result.MaxError, r.norm());
  }
  result.Rmse = std::sqrt(sum / static_cast<double>(n));
  for (int k = 0; k < 3; ++k) {
    result.TipOffset[static_cast<size_t>(k)] = x[k];
    result.PivotPoint[static_cast<size_t>(k)] = x[k + 3];
  }
  result.Valid = true;
  result.Accepted = result.Rmse <= thresholdMm;
  if (!result.Accepted)
    result.Message = "pivot RMSE " + std::to_string(result.Rmse) + " mm exceeds the threshold of " + std::to_string(thresholdMm) + " mm";
  return result;
}

ToolPose ToolToReference(const ToolPose& tool, const ToolPose& reference) {
  const Eigen::Quaterniond qt(tool.Quaternion[0], tool.Quaternion[1], tool.Quaternion[2], tool.Quaternion[3]);
  const Eigen::Quaterniond qr(reference.Quaternion[0], reference.Quaternion[1], reference.Quaternion[2], reference.Quaternion[3]);
  const Eigen::Quaterniond qrInv = qr.conjugate();
  const Eigen::Quaterniond q = (qrInv * qt).normalized();
  const Eigen::Vector3d t = qrInv * (Eigen::Vector3d(tool.Translation) - Eigen::Vector3d(reference.Translation));
  ToolPose out = tool;
  out.Quaternion[0] = q.w();
  out.Quaternion[1] = q.x();
  out.Quaternion[2] = q.y();
  out.Quaternion[3] = q.z();
  for (int k = 0; k < 3; ++k) out.Translation[k] = t[k];
  out.Timestamp = std::min(tool.Timestamp, reference.Timestamp);
  out.ReceiveTime = std::min(tool.ReceiveTime, reference.ReceiveTime);
  out.State = tool.State != ToolState::OK ? tool.State : reference.State;
  return out;
}

void TipOffsetMatrix(const std::array<double, 3>& tip, double m[16]) {
  for (int i = 0; i < 16; ++i) m[i] = (i % 5 == 0) ? 1.0 : 0.0;
  m[3] = tip[0];
  m[7] = tip[1];
  m[11] = tip[2];
}

}  // namespace rp
