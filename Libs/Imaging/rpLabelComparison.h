#pragma once
// A segmentation scored against a truth labelmap, label by label: Dice and the symmetric
// surface distance (mean, 95th percentile, maximum) between the two labels' boundary voxels, in
// mm. Each label is matched to the truth label it overlaps most (so label numbers need not agree).
// The truth is sampled (nearest voxel, through both IJK-to-RAS matrices) onto the segmentation's
// grid when the grids differ.
#include <string>
#include <vector>

#include "rpImageVolume.h"

namespace rp {

struct LabelScore {
  int Label = 0;
  int TruthLabel = 0;  // 0: overlaps no truth label
  long long Voxels = 0, TruthVoxels = 0, OverlapVoxels = 0;
  double Dice = 0.0;
  double MeanSurfaceDistanceMm = -1.0, Hausdorff95Mm = -1.0, HausdorffMm = -1.0;  // -1: no truth label
};

struct LabelComparison {
  std::vector<LabelScore> Scores;   // one per label asked for, in order
  std::vector<int> UnmatchedTruth;  // truth labels no label was matched to
  bool TruthResampled = false;
};

/// Scores `labels` of `test` (all non-zero values when empty) against `truth`. False with `error`
/// when an image is empty or has no labels.
bool CompareLabels(const ImageVolume& test, const ImageVolume& truth, std::vector<int> labels,
                   LabelComparison& result, std::string& error);

}  // namespace rp
