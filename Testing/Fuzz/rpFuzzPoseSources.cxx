// The pose-source list for rpPlusSequenceFuzzer, which reads sequence files and creates no pose
// source (the module's own list is Modules/Loadable/Tracking/Logic/rpPoseSourceKinds.cxx).
#include "rpPoseSourceKinds.h"

namespace rp {

std::vector<PoseSourceRegistry::Entry> BuiltInPoseSources() { return {}; }

}  // namespace rp
