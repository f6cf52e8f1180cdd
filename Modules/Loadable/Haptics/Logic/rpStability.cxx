#include "rpStability.h"

#include <algorithm>
#include <cmath>

namespace rp {

double PassiveStiffnessLimit(const DeviceInfo& device, double period, double damping) {
  double limit = device.NominalMaxStiffness;
  if (device.PhysicalDamping > 0 && period > 0)
    limit = std::min(limit, std::max(0.0, 2.0 * (device.PhysicalDamping - std::fabs(damping)) / period));
  return limit;
}

GainLimits LimitGains(double k, double b, const DeviceInfo& device, double period, double scale) {
  GainLimits g;
  scale = scale > 0 ? scale : 1.0;
  double bAllowed = std::min(b, device.NominalMaxDamping);
  if (device.PhysicalDamping > 0) bAllowed = std::min(bAllowed, 0.5 * device.PhysicalDamping);
  bAllowed = std::max(0.0, bAllowed);
  const double kDevice = k * scale;
  // Stay 10 % inside the passive bound: at the bound itself a wall is only marginally stable
  // (a sustained oscillation in the benchmark's simulated device).
  double kAllowed = std::min(kDevice, device.NominalMaxStiffness);
  if (device.PhysicalDamping > 0 && period > 0)
    kAllowed = std::min(kAllowed, PassiveSafetyFraction * 2.0 * (device.PhysicalDamping - bAllowed) / period);
  g.StiffnessScale = kDevice > 0 ? kAllowed / kDevice : 1.0;
  g.DampingScale = b > 0 ? bAllowed / b : 1.0;
  g.Stiffness = kAllowed;
  g.Damping = bAllowed;
  g.Margin = device.PhysicalDamping > 0 ? device.PhysicalDamping - (kAllowed * period / 2 + bAllowed) : 0.0;
  return g;
}

}  // namespace rp
