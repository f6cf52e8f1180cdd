#pragma once
// Stiffness and damping a sampled haptic device keeps passive. Colgate & Schenkel (1997): a
// virtual wall K, B sampled every T on a device with physical damping b is passive when
//     b > K·T/2 + |B|.
// Contacts act in parallel, so the limit applies to the summed K and B of all contact points.
#include "rpHapticDevice.h"

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

}  // namespace rp
