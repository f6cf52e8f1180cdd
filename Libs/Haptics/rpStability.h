#pragma once
// Stiffness and damping a sampled haptic device keeps passive. Colgate & Schenkel (1997): a
// virtual wall K, B sampled every T on a device with physical damping b is passive when
//     b > K·T/2 + |B|.
// Contacts act in parallel, so the limit applies to the summed K and B of all contact points.
#include <string>
#include <vector>

#include "rpHapticDevice.h"
#include "rpMaterial.h"

namespace rp {

struct GainLimits {
  double StiffnessScale = 1;  // multiply every contact's k by this
  double DampingScale = 1;    // multiply every contact's b by this
  double Stiffness = 0;       // effective summed K at the device (N/mm)
  double Damping = 0;         // effective summed B (N·s/mm)
  double Margin = 0;          // b − (K·T/2 + |B|), N·s/mm (≥ 0: passive); 0 when b unknown
};

/// LimitGains keeps the summed stiffness at this fraction of the passive bound.
constexpr double PassiveSafetyFraction = 0.9;

/// Largest stiffness the Colgate-Schenkel condition allows for damping B (0 when b ≤ |B|).
/// With an unknown physical damping (b ≤ 0) only the device's nominal limit applies.
double PassiveStiffnessLimit(const DeviceInfo& device, double period, double damping);

/// Scales summed contact gains into the device's passive region. `workspaceScale` multiplies
/// stiffness as the device feels it (a scene mm per device mm scales K by that factor).
/// Virtual damping gets at most half the physical damping budget; stiffness the rest, times
/// PassiveSafetyFraction.
GainLimits LimitGains(double summedStiffness, double summedDamping, const DeviceInfo& device, double period,
                      double workspaceScale = 1.0);

/// The device's limits left to one contact when others (other contact points, virtual fixtures)
/// already render `otherStiffness` and `otherDamping` this tick: contacts act in parallel, so they
/// share the nominal maxima and the physical damping's passive budget. Numbers only (no name:
/// copying it could allocate on the servo thread).
DeviceInfo RemainingBudget(const DeviceInfo& device, double otherStiffness, double otherDamping, double period) noexcept;

/// What one tissue asks for and what the device renders of it (a single contact through
/// LimitGains, so the same numbers the servo loop uses). Stiffness in N/mm and damping in
/// N·s/mm, both as the scene sees them.
struct MaterialClamp {
  std::string Tissue;
  double RequestedStiffness = 0, RenderedStiffness = 0;
  double RequestedDamping = 0, RenderedDamping = 0;
  std::string Limit;  // what bounds the stiffness when clamped: the nominal maximum or passivity at T
  bool Clamped() const;
};

/// Every material of the table through the device's limits at servo period `period` (s).
std::vector<MaterialClamp> ClampMaterials(const std::vector<Material>& materials, const DeviceInfo& device,
                                          double period, double workspaceScale = 1.0);
/// "bone: stiffness 0.70 N/mm is above what Touch (simulated) renders stably (...); rendered at 0.40 N/mm".
std::string ClampWarning(const MaterialClamp& clamp, const DeviceInfo& device);

}  // namespace rp
