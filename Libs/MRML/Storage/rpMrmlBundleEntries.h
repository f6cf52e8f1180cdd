#pragma once
// Internal to RoboPlanMRMLStorage: the entries of libRoboPlanMrmlBundle.so (rpMrmlBundle.cxx, the
// libarchive side of .mrb bundles) that rp::UnpackBundle and rp::PackBundle forward to
// (rpMrmlBundleLoader.cxx), loaded on the first bundle. Their names and types in one place for
// both sides; the types are the C++ functions' own (rpMrmlBundle.h).
#include "rpMrmlBundle.h"

#define RP_BUNDLE_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::bundle {

constexpr const char* Library = "libRoboPlanMrmlBundle.so";

/// roboplan_unpack_bundle / roboplan_pack_bundle: what rp::UnpackBundle / rp::PackBundle do.
using UnpackFunction = decltype(&UnpackBundle);
constexpr const char* UnpackEntry = "roboplan_unpack_bundle";
using PackFunction = decltype(&PackBundle);
constexpr const char* PackEntry = "roboplan_pack_bundle";

}  // namespace rp::bundle
