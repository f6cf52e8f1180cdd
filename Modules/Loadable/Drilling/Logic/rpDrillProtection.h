#pragma once
// Structures at risk in the drillable bone: one notion with the plan's (a model or segment with a
// safety margin) and the drilling's protected segments. The bone within a structure's margin of its
// surface is protected, so the burr refuses to cut there (rpBoneCutter) — less two voxels, so that
// a burr held at the margin by the forbidden-region fixture (rpForbiddenRegion) still cuts, its
// cut reaching one voxel beyond its sphere. Done once the bone is built, before a servo runs.
#include <memory>
#include <string>
#include <vector>

#include "rpDrillVolume.h"
#include "rpMeshSignedDistance.h"

namespace rp {

struct ProtectedRegion {
  std::string Name;
  std::shared_ptr<const MeshSignedDistance> Surface;  // closed, RAS
  double MarginMm = 0;
};

/// Marks the stored bone voxels within each region's margin (less two voxels); returns how many.
size_t ProtectRegions(DrillVolume& bone, const std::vector<ProtectedRegion>& regions);

}  // namespace rp
