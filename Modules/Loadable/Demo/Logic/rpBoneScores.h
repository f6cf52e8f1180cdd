#pragma once
// Scores bone segments against a ground truth, per bone: Dice of the voxels, and mean, 95 % and
// largest distance between each bone's mesh and the true surface (both directions, inside a
// box). Truth bones come from the phantom (its labels and true surfaces) or from a labelmap
// (each label value a bone; its surface meshed from the labels). Each truth bone is matched
// with the bone segment that overlaps it most, so the segments' names need not match the truth's.
#include <functional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpSurfaceError.h"

class vtkImageData;
class vtkMatrix4x4;
class vtkPolyData;
class vtkRPSegmentationNode;

namespace rp {

struct ImageVolume;
class KneeModel;

struct TruthBone {
  std::string Name;                // "Tibia", or "label 1" for an unnamed labelmap
  std::vector<unsigned char> Mask;  // on the segmentation's grid
  SignedDistanceFunction Distance;  // to the true surface
  std::vector<std::array<double, 3>> SurfacePoints;
};

struct BoneScore {
  std::string Truth;          // the truth bone's name
  std::string SegmentID;      // the matched segment ("" when none overlaps)
  std::string SegmentName;
  double Dice = 0;
  bool HasSurface = false;    // the segment has a mesh to compare
  SurfaceError Surface;
};

/// Truth bones of the knee phantom (labels on the segmentation's grid, as the phantom's CT is).
std::vector<TruthBone> PhantomTruthBones(const ImageVolume& labels, const KneeModel& model,
                                         vtkRPSegmentationNode* segmentation, std::string& error);
/// Truth bones from a labelmap (any grid: sampled at the segmentation's voxel centres); each
/// non-zero value is a bone, named from `names` (value → name) or "label N".
std::vector<TruthBone> LabelmapTruthBones(const ImageVolume& labels, const std::vector<std::string>& names,
                                          vtkRPSegmentationNode* segmentation, std::string& error);

/// Scores every truth bone. `meshOf(segmentID)` gives the segment's mesh (or null).
std::vector<BoneScore> ScoreBones(const std::vector<TruthBone>& truth, vtkRPSegmentationNode* segmentation,
                                  const std::function<vtkPolyData*(const std::string&)>& meshOf,
                                  const double clipBounds[6]);

}  // namespace rp
