#pragma once
// Builds the drillable bone from a segmentation: the bone segments' labels (any integer
// labelmap, any orientation) are resampled onto an axis-aligned RAS grid of the chosen voxel
// size. The density is the two-voxel ramp around the surface of the trilinearly interpolated
// label mask (its ½ iso-surface: where marching cubes would put the segment's surface), so the
// bone is smooth at 0.2 mm even from a 1 mm labelmap. Each bone voxel gets a material:
//  - with a CT: by its HU, the drillable material with the highest ctMinHU at or below it
//    (materials.json: cortical "bone" ≥ 600 HU, "trabecular bone" below); in the surface ramp
//    the brightest of the 8 CT voxels around it is used (partial volume thins the cortex);
//  - without: the segment's tissue class when it is drillable, else the first drillable one.
// Protected segments mark their voxels protected; one of a drillable tissue (e.g. the posterior
// cortex) is solid bone the burr feels and never removes, another (a nerve's region) is space the
// burr may enter but not cut in. Their own surface is built alongside for the distance read-out. Only blocks near bone or protected voxels are stored.
#include <string>
#include <vector>

#include "rpDrillVolume.h"
#include "rpImageVolume.h"
#include "rpProgress.h"

namespace rp {

struct DrillBoneSource {
  ImageVolume Labels;                    // the labelmap (integer scalars), RAS geometry
  std::vector<int> BoneLabels;           // label values of the bone to drill
  std::vector<std::string> BoneTissues;  // tissue class per bone label ("" = unknown)
  std::vector<int> ProtectedLabels;      // label values of protected structures
  std::vector<std::string> ProtectedTissues;  // their tissue classes: a drillable one (bone) is solid
  ImageVolume CT;                        // optional: HU for cortical / trabecular
  double Spacing = 0.3;                  // drill voxel size (mm)
  bool HasRegion = false;                // limit the grid to this RAS box
  Vec3 RegionLo, RegionHi;
};

struct DrillBoneReport {
  size_t GridVoxels = 0, StoredBlocks = 0;
  double MemoryMB = 0, Seconds = 0;
  std::vector<double> VolumeMm3;  // per drillable material, as built
  bool UsedCT = false;
  bool HasProtected = false;
};

/// Builds `bone` (and, when `protectedSurface` is given and protected labels exist, a volume
/// whose ½ iso-surface is the protected structures' surface, for rpBlockMesher → BVH).
/// `materials` are the drillable materials (DrillableMaterials of the table). False names the
/// problem (no bone voxel, unknown label, grid too large, ...).
bool BuildDrillBone(const DrillBoneSource& source, const std::vector<Material>& materials, DrillVolume& bone,
                    DrillVolume* protectedSurface, DrillBoneReport& report, std::string& error,
                    const ProgressCallback& progress = nullptr);

}  // namespace rp
