#pragma once
// Builds the drillable bone from a segmentation: the bone segments' labels (any integer
// labelmap, any orientation) are resampled onto an axis-aligned RAS grid of the chosen voxel
// size. The density is the two-voxel ramp around the bone's smooth surface: the signed distance
// (rp::MeshSignedDistance over the project's BVH) from each voxel centre to the segment's closed
// mesh, either given (the bone model the user sees) or made here from the bone labels the way
// the segment models are made (rp::LabelmapToMesh, Gaussian, σ = 1 voxel, volume-corrected). So
// the drilled bone shows, and the burr feels, the bone model's surface until the burr cuts it,
// not the labelmap's staircase (a 0.8 × 0.8 × 1.25 mm labelmap's trilinear mask keeps
// millimetre steps at a 0.3 mm drill grid). Distances are computed per 4³ sub-block first: a
// sub-block whose centre is farther from the surface than its half-diagonal plus a voxel is
// all bone or all air without a query per voxel. SmoothSurface off gives the former ramp around
// the trilinearly interpolated label mask. Each bone voxel gets a material:
//  - with a CT: by its HU, the drillable material with the highest ctMinHU at or below it
//    (materials.json: cortical "bone" ≥ 600 HU, "trabecular bone" below); in the surface ramp
//    the brightest of the 8 CT voxels around it is used (partial volume thins the cortex);
//  - without: the segment's tissue class when it is drillable, else the first drillable one.
// Protected segments mark their voxels protected; one of a drillable tissue (e.g. the posterior
// cortex) is solid bone the burr feels and never removes, another (a nerve's region) is space the
// burr may enter but not cut in. Their own surface is built alongside for the distance read-out. Only blocks near bone or protected voxels are stored.
// MeasureSurfaceFit tells how closely a built bone follows a mesh (the tests, the demo's report).
#include <memory>
#include <string>
#include <vector>

#include "rpDrillVolume.h"
#include "rpImageVolume.h"
#include "rpMeshSignedDistance.h"
#include "rpProgress.h"
#include "rpTriangleMesh.h"

class vtkRPSegmentationNode;

namespace rp {

/// Segments of a segmentation node, as a drill bone takes them.
struct DrillSegments {
  std::vector<int> Labels;
  std::vector<std::string> Tissues, IDs, Names;  // a segment without a name is named by its ID
};
/// The segments `refs` name (each an ID, a name in any case, or a label value), appended to
/// `found`. False names the first unknown reference and lists the segments.
bool FindDrillSegments(vtkRPSegmentationNode* segmentation, const std::vector<std::string>& refs, DrillSegments& found,
                       std::string& error);

struct DrillBoneSource {
  ImageVolume Labels;                    // the labelmap (integer scalars), RAS geometry
  std::vector<int> BoneLabels;           // label values of the bone to drill
  std::vector<std::string> BoneTissues;  // tissue class per bone label ("" = unknown)
  std::vector<int> ProtectedLabels;      // label values of protected structures
  std::vector<std::string> ProtectedTissues;  // their tissue classes: a drillable one (bone) is solid
  ImageVolume CT;                        // optional: HU for cortical / trabecular
  double Spacing = 0.3;                  // drill voxel size (mm)
  bool SmoothSurface = true;             // density from the bone's smooth surface (else the label mask)
  TriangleMesh BoneSurface;              // closed, RAS; empty: meshed here from the bone labels
  bool HasRegion = false;                // limit the grid to this RAS box
  Vec3 RegionLo, RegionHi;
};

struct DrillBoneReport {
  size_t GridVoxels = 0, StoredBlocks = 0;
  double MemoryMB = 0, Seconds = 0;
  std::vector<double> VolumeMm3;  // per drillable material, as built
  bool UsedCT = false;
  bool HasProtected = false;
  std::string Surface;            // what the density follows: "given mesh", "labels meshed here", "label mask"
  size_t SurfaceTriangles = 0;
  /// That surface (closed, RAS; null for the label mask): the bone an execution's breach is
  /// measured against (rpExecutionScore.h).
  std::shared_ptr<const MeshSignedDistance> BoneSurface;
};

/// Builds `bone` (and, when `protectedSurface` is given and protected labels exist, a volume
/// whose ½ iso-surface is the protected structures' surface, for rpBlockMesher → BVH).
/// `materials` are the drillable materials (DrillableMaterials of the table). False names the
/// problem (no bone voxel, unknown label, grid too large, ...).
bool BuildDrillBone(const DrillBoneSource& source, const std::vector<Material>& materials, DrillVolume& bone,
                    DrillVolume* protectedSurface, DrillBoneReport& report, std::string& error,
                    const ProgressCallback& progress = nullptr);

/// How closely a built bone follows `surface` (e.g. the bone model it was built from): distances
/// (mm) from the vertices of its ½ iso-surface (rpBlockMesher, as it is now) to `surface`.
/// Vertices within two voxels of the grid's faces are left out: there the grid, not the surface,
/// bounds the bone (a region cuts it).
struct SurfaceFit {
  double MeanMm = 0, P95Mm = 0, MaxMm = 0;
  size_t Vertices = 0;  // vertices measured
};
SurfaceFit MeasureSurfaceFit(DrillVolume& bone, const TriangleMesh& surface);

}  // namespace rp
