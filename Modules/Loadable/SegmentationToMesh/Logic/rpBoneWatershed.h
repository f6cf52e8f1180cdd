#pragma once
// Touching bones told apart (the steps of rpBoneSplit.cxx): seeds placed on bone and climbed to
// their basin's deepest point, a watershed of the distance to the bone surface that keeps two
// regions apart where the contact between them is a narrow neck (a joint), and small groups
// (bumps of a bone) merged into the neighbour they touch most. Internal to SplitBones.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "rpBoneMasks.h"

class vtkRPImageNode;

namespace rp::bonesplit {

/// Seeds onto bone (the nearest bone voxel within 5 mm), then up to their basin's deepest point;
/// seeds of one name share a name index (unnamed seeds are all distinct). False with `error` for
/// a seed that is not on bone.
bool PlaceSeeds(vtkRPImageNode* ct, const BoneSplitOptions& options, const Box& box, const double spacing[3],
                const std::vector<uint8_t>& mask, const std::vector<float>& distance, std::vector<size_t>& seedVoxels,
                std::vector<int>& seedName, std::string& error);

/// Watershed of the distance map from its deepest points down, merging regions as rpBoneSplit.h
/// describes. `seedVoxels[s]` = box index where seed s sits (its basin's deepest point). Returns
/// per-voxel group (root region id + 1, 0 = background) and the number of kept splits; pairs of
/// differently named seeds that reach one deepest point go to `seedConflicts`.
int Watershed(const std::vector<float>& distance, const std::vector<uint8_t>& mask, const Box& box,
              const BoneSplitOptions& options, const std::vector<size_t>& seedVoxels, const std::vector<int>& seedName,
              std::vector<int32_t>& group, std::vector<std::pair<int, int>>& seedConflicts);

/// Groups smaller than `minVoxels` (bumps of a bone) join the neighbour they touch most.
void MergeSmallGroups(std::vector<int32_t>& group, const Box& box, long minVoxels);

}  // namespace rp::bonesplit
