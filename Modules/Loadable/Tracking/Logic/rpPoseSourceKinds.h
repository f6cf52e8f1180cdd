#pragma once
// Every kind of pose source the Tracking module brings, listed in one place (as PLUS lists its
// devices in one factory) instead of each registering itself from a static initializer: the
// registry (rpPoseSource.h) starts from this list. A new tracker: its class, then one line here.
#include <vector>

#include "rpPoseSource.h"

namespace rp {

std::vector<PoseSourceRegistry::Entry> BuiltInPoseSources();

}  // namespace rp
