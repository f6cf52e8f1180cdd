#include "rpStability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

DeviceInfo RemainingBudget(const DeviceInfo& device, double otherStiffness, double otherDamping, double period) noexcept {
  DeviceInfo budget;
  budget.MaxForce = device.MaxForce;
  budget.MaxForceRate = device.MaxForceRate;
  budget.MaxTorque = device.MaxTorque;
  budget.NominalMaxStiffness = std::max(0.0, device.NominalMaxStiffness - otherStiffness);
  budget.NominalMaxDamping = std::max(0.0, device.NominalMaxDamping - otherDamping);
  budget.PhysicalDamping = device.PhysicalDamping;
  if (budget.PhysicalDamping > 0)
    budget.PhysicalDamping = std::max(0.0, budget.PhysicalDamping - (otherStiffness * period / 2 + otherDamping));
  return budget;
}

bool MaterialClamp::Clamped() const {
  return this->RenderedStiffness < this->RequestedStiffness * (1 - 1e-9) ||
         this->RenderedDamping < this->RequestedDamping * (1 - 1e-9);
}

std::vector<MaterialClamp> ClampMaterials(const std::vector<Material>& materials, const DeviceInfo& device,
                                          double period, double workspaceScale) {
  std::vector<MaterialClamp> clamps;
  for (const Material& m : materials) {
    const GainLimits g = LimitGains(m.Stiffness, m.Damping, device, period, workspaceScale);
    MaterialClamp c;
    c.Tissue = m.Tissue;
    c.RequestedStiffness = m.Stiffness;
    c.RenderedStiffness = m.Stiffness * g.StiffnessScale;
    c.RequestedDamping = m.Damping;
    c.RenderedDamping = m.Damping * g.DampingScale;
    if (c.RenderedStiffness < c.RequestedStiffness * (1 - 1e-9)) {
      char text[160];
      if (g.Stiffness >= device.NominalMaxStiffness * (1 - 1e-9))
        std::snprintf(text, sizeof(text), "the device's nominal maximum %.2f N/mm", device.NominalMaxStiffness);
      else
        std::snprintf(text, sizeof(text), "passivity (Colgate-Schenkel) at a %.2f ms servo period", period * 1e3);
      c.Limit = text;
    } else if (c.Clamped()) {
      c.Limit = "the device's damping budget";
    }
    clamps.push_back(c);
  }
  return clamps;
}

std::string ClampWarning(const MaterialClamp& c, const DeviceInfo& device) {
  char text[400];
  if (c.RenderedStiffness < c.RequestedStiffness * (1 - 1e-9))
    std::snprintf(text, sizeof(text), "%s: stiffness %.2f N/mm is above what %s renders stably (%s); rendered at %.2f N/mm",
                  c.Tissue.c_str(), c.RequestedStiffness, device.Name.c_str(), c.Limit.c_str(), c.RenderedStiffness);
  else
    std::snprintf(text, sizeof(text), "%s: damping %.4f N*s/mm is above what %s renders stably (%s); rendered at %.4f N*s/mm",
                  c.Tissue.c_str(), c.RequestedDamping, device.Name.c_str(), c.Limit.c_str(), c.RenderedDamping);
  return text;
}

}  // namespace rp
