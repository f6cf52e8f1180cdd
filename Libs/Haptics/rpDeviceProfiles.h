#pragma once
// Device profiles for the simulated device, chosen by name in the CLI (`--device`) and the
// Haptics panel: the limits of a real device of that model, so the simulation renders nothing
// the hardware could not. A new profile is one entry in DeviceProfiles().
#include <string>
#include <vector>

#include "rpHapticDevice.h"

namespace rp {

struct DeviceProfile {
  std::string Key;    // what users type: "omni", "touch"
  DeviceInfo Info;    // limits (Info.Name is the display name)
  std::string Notes;  // where the numbers come from
};

/// Every profile; the first is the default (the seed paper's Phantom Omni).
const std::vector<DeviceProfile>& DeviceProfiles();
/// "omni", "touch" (case-insensitive; the display name works too). False and `error` lists the
/// known names when there is no such profile.
bool FindDeviceProfile(const std::string& name, DeviceProfile& profile, std::string& error);
/// "omni|touch", for usage lines.
std::string DeviceProfileKeys();

}  // namespace rp
