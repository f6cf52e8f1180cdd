// What RoboPlanImaging holds of CT-MR registration (rpVolumeRegistration.h): the forwarder to the
// ITK side in libRoboPlanVolumeRegistration.so beside this library (rpVolumeRegistrationEntry.h),
// loaded on the first registration, and the transform comparison, which needs no ITK.
#include <cmath>

#include "rpSiblingLibrary.h"
#include "rpVolumeRegistrationEntry.h"

namespace rp {

bool RegisterVolumesRigid(const ImageVolume& fixed, const ImageVolume& moving, const RigidRegistrationOptions& options,
                          RigidRegistrationResult& result, std::string& error, const ProgressCallback& progress,
                          const std::atomic<bool>* cancel) {
  std::string why;
  const auto registerRigid = SiblingLibraryFunction<registration::RigidFunction>(
      reinterpret_cast<const void*>(&RegisterVolumesRigid), registration::Library, registration::RigidEntry, why);
  if (!registerRigid) {
    error = "CT-MR registration is not available: " + why;
    return false;
  }
  return registerRigid(fixed, moving, options, result, error, progress, cancel);
}

double TransformRMSDifference(const vtkMatrix4x4* a, const vtkMatrix4x4* b,
                              const std::vector<std::array<double, 3>>& points) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& p : points) {
    const double in[4] = {p[0], p[1], p[2], 1.0};
    double pa[4], pb[4];
    const_cast<vtkMatrix4x4*>(a)->MultiplyPoint(in, pa);
    const_cast<vtkMatrix4x4*>(b)->MultiplyPoint(in, pb);
    sum += (pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) + (pa[2] - pb[2]) * (pa[2] - pb[2]);
  }
  return std::sqrt(sum / points.size());
}

}  // namespace rp
