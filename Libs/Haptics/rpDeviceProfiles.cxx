#include "rpDeviceProfiles.h"

#include <algorithm>
#include <cctype>

#include "rpStrings.h"

namespace rp {

namespace {
DeviceProfile Make(const char* key, const char* name, double maxForce, double maxStiffness, const char* notes) {
  DeviceProfile p;
  p.Key = key;
  p.Info.Name = name;
  // 160 W x 120 H x 70 D mm (seed paper, section 2.2), centred on the device origin.
  p.Info.WorkspaceMin = {-80, -60, -35};
  p.Info.WorkspaceMax = {80, 60, 35};
  p.Info.MaxForce = maxForce;
  p.Info.NominalMaxStiffness = maxStiffness;
  p.Info.NominalMaxDamping = 0.002;
  // The mechanism's own damping (Colgate-Schenkel's b) is not published and the HD API does
  // not report it: the simulated mechanism's value (45 g, 3 N·s/m), as the benchmark models it.
  p.Info.PhysicalDamping = 0.003;
  // Events (a fixture switched, captured, released) change the force no faster than the stiffest
  // spring this device renders does under a hand moving at 0.5 m/s.
  p.Info.MaxForceRate = maxStiffness * 500.0;
  p.Info.MaxTorque = 0;  // 3-DoF force output
  p.Notes = notes;
  return p;
}
}  // namespace

const std::vector<DeviceProfile>& DeviceProfiles() {
  static const std::vector<DeviceProfile> profiles = {
      Make("omni", "Phantom Omni (simulated)", 3.3, 0.7,
           "SensAble/3D Systems Phantom Omni, the seed paper's device: 3.3 N peak force, about 0.7 N/mm nominal "
           "maximum stiffness, 160 x 120 x 70 mm workspace"),
      Make("touch", "Touch (simulated)", 3.3, 0.4,
           "3D Systems Touch: 3.3 N peak force, about 0.4 N/mm nominal maximum stiffness, 160 x 120 x 70 mm "
           "workspace"),
  };
  return profiles;
}

bool FindDeviceProfile(const std::string& name, DeviceProfile& profile, std::string& error) {
  const std::string key = Lower(name);
  for (const DeviceProfile& p : DeviceProfiles()) {
    if (Lower(p.Key) == key || Lower(p.Info.Name) == key) {
      profile = p;
      return true;
    }
  }
  error = "unknown haptic device '" + name + "' (known: " + DeviceProfileKeys() + ")";
  return false;
}

std::string DeviceProfileKeys() {
  std::string keys;
  for (const DeviceProfile& p : DeviceProfiles()) keys += (keys.empty() ? "" : "|") + p.Key;
  return keys;
}

}  // namespace rp
