#pragma once
// Bones one by one from a CT: one segment per bone, also where bones touch once thresholded
// (tibia–fibula at the proximal tibiofibular joint, femur–patella, femur–tibia through a thin
// joint space).
//
//  1. bone = lower <= HU <= upper (low, so a thin cortex is kept), holes filled in 3-D and
//     slice by slice along every axis (marrow behind a cortex with gaps, shafts cut open by the
//     field of view);
//  2. the body outline (HU > -400 on a ~2 mm grid, opened by 4 mm so a table shell or a cable
//     falls off, holes filled); bone pieces mostly outside it (CT table, positioning aids,
//     cables) and specks smaller than MinBoneMl are dropped;
//  3. touching bones are split by a watershed on the distance to the bone surface: flooding
//     from the deepest points down, two regions that meet are one bone when the neck between
//     them is nearly as thick as the thinner region (saddle >= NeckRatio x its depth, or less
//     than MinDepthMm shallower); a narrow contact (a joint) keeps them apart. Seeds (RAS)
//     name bones and force a split: regions holding differently named seeds never merge;
//  4. each bone is closed (FillRadiusMm) and filled on its own, so no joint space is filled,
//     and its surface voxels below the local half maximum are peeled: the edge sits half way
//     between the bone's local peak (a thin cortex has a low partial-volume peak) and the soft
//     tissue beside it, not at the low threshold that found the bone;
//  5. bones are named from seeds, then knee bones from position and size (rpKneeBoneNames:
//     tibia = the large bone with a slender fibula behind it, femur = pieces above the tibial
//     plateau, patella = small and anterior at the joint), the rest "Bone N". Pieces with one
//     name (condyles cut by the field of view) become one segment.
#include <array>
#include <string>
#include <vector>

#include "rpProgress.h"

class vtkRPImageNode;
class vtkRPSegmentationNode;

namespace rp {

struct BoneSeed {
  std::array<double, 3> RAS = {0, 0, 0};
  std::string Name;  // empty: the seed only forces a split
};

struct BoneSplitOptions {
  double LowerHU = 200, UpperHU = 3071;
  /// Body outline threshold (HU) and opening radius (mm) that detaches a CT table or cables.
  double BodyLowerHU = -400, BodyOpeningMm = 4.0;
  /// Pieces smaller than this (ml) are dropped as specks.
  double MinBoneMl = 0.3;
  /// Each bone, once split, is closed with a ball of this radius and its holes filled (marrow,
  /// low-density trabecular bone behind a thin cortex).
  double FillRadiusMm = 3.0;
  /// The bone's edge: surface voxels below the local half maximum between the bone's densest
  /// voxel within EdgePeakMm and the soft tissue beside it are peeled (EdgeLayers passes; 0 =
  /// none). EdgeHU > 0: a fixed edge instead.
  double EdgeHU = 0;
  double EdgePeakMm = 2.0;
  int EdgeLayers = 1;
  /// Watershed merge rule (see above).
  double NeckRatio = 0.6, MinDepthMm = 1.5;
  std::vector<BoneSeed> Seeds;
  /// Name femur/tibia/fibula/patella from position and size (else every bone is "Bone N").
  bool NameKneeBones = true;
  std::string TissueClass = "bone";
};

struct BoneInfo {
  std::string ID, Name;
  int LabelValue = 0;
  long Voxels = 0;
  double VolumeMl = 0;
  double CentroidRAS[3] = {0, 0, 0};
  double BoundsRAS[6] = {0, 0, 0, 0, 0, 0};
  std::string NamedBy;  // "seed", "knee anatomy" or "" (Bone N)
};

struct BoneSplitResult {
  std::vector<BoneInfo> Bones;  // largest first
  long ThresholdVoxels = 0;     // after closing and hole filling
  int DroppedOutsideBody = 0;   // pieces outside the body outline (table, cables)
  double DroppedOutsideBodyMl = 0;
  int DroppedSpecks = 0;
  double DroppedSpecksMl = 0;
  int Splits = 0;               // touching bones separated (watershed boundaries kept)
  std::vector<std::string> Notes;
  double Seconds = 0;
};

/// Fills `segmentation` (a new labelmap on the CT's grid, previous segments removed) with one
/// segment per bone, tissue class options.TissueClass. False with `error` (segmentation left
/// as it was) when the CT is unusable, no bone is found, or a seed lies off bone.
bool SplitBones(vtkRPImageNode* ct, vtkRPSegmentationNode* segmentation, const BoneSplitOptions& options,
                BoneSplitResult& result, std::string& error, const ProgressCallback& progress = nullptr);

/// "R,A,S" or "R,A,S:name" (RAS mm). False with `error` naming the text.
bool ParseBoneSeed(const std::string& text, BoneSeed& seed, std::string& error);

}  // namespace rp
