#pragma once
// Internal to RoboPlanImaging and libRoboPlanVolumeRegistration.so: the entry through which
// rp::RegisterVolumesRigid (rpVolumeRegistration.h; its forwarder: rpVolumeRegistrationLoader.cxx)
// reaches the ITK registration (rpVolumeRegistration.cxx), loaded on the first registration. Its
// name and type in one place for both sides; the type is the C++ function's own. ITK's v4
// registration, optimizers, transforms and smoothing (6 libraries with ours) are then mapped only
// by a program that registers, not by every command of the modules that can.
#include "rpVolumeRegistration.h"

#define RP_REGISTRATION_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::registration {

constexpr const char* Library = "libRoboPlanVolumeRegistration.so";

/// roboplan_register_volumes_rigid: what rp::RegisterVolumesRigid does.
using RigidFunction = decltype(&RegisterVolumesRigid);
constexpr const char* RigidEntry = "roboplan_register_volumes_rigid";

}  // namespace rp::registration
