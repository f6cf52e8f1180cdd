#pragma once
// Masks over the box that holds a CT's bone (the steps of rpBoneSplit.cxx): hole filling,
// connected components, the body outline, each bone made solid, its edge put where the CT says
// it is, and the distance to the bone surface. Internal to SplitBones (namespace rp::bonesplit).
// The morphology and the distance map run ITK in libRoboPlanSegmentationItk.so, loaded on their
// first call (rpSegmentationItkEntries.h): the functions that use them return false with an error
// when it cannot load.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rpBoneSplit.h"
#include "rpSegmentationEditor.h"

class vtkImageData;

namespace rp::bonesplit {

// A box of the CT (voxel index range) holding every bone voxel; masks over it are vectors in
// its index order (x fastest).
struct Box {
  int Lo[3] = {0, 0, 0}, Size[3] = {0, 0, 0};
  size_t Count() const { return static_cast<size_t>(this->Size[0]) * this->Size[1] * this->Size[2]; }
  size_t Index(int i, int j, int k) const {
    return (static_cast<size_t>(k) * this->Size[1] + static_cast<size_t>(j)) * this->Size[0] + static_cast<size_t>(i);
  }
  void Coords(size_t idx, int c[3]) const {
    const size_t nx = static_cast<size_t>(this->Size[0]), ny = static_cast<size_t>(this->Size[1]);
    c[0] = static_cast<int>(idx % nx), c[1] = static_cast<int>((idx / nx) % ny), c[2] = static_cast<int>(idx / (nx * ny));
  }
};

// Calls f(neighbour index) for the face neighbours of `idx` inside [lo, hi] (voxel ranges).
template <typename F>
void ForFaceNeighbours(const Box& box, size_t idx, const int lo[3], const int hi[3], F&& f) {
  int c[3];
  box.Coords(idx, c);
  for (int a = 0; a < 3; ++a)
    for (int d : {-1, 1}) {
      int q[3] = {c[0], c[1], c[2]};
      q[a] += d;
      if (q[a] < lo[a] || q[a] > hi[a]) continue;
      f(box.Index(q[0], q[1], q[2]));
    }
}

/// Background reachable from the box border (6-connected) stays background; the rest is filled.
/// With `sliceAxis` >= 0 the flood runs in each slice across that axis separately (2-D holes).
void FillHoles(std::vector<uint8_t>& mask, const Box& box, int sliceAxis);

/// 6-connected components of a mask: labels 1..N (0 = background), voxel count per label.
int Components(const std::vector<uint8_t>& mask, const Box& box, std::vector<int32_t>& labels,
               std::vector<long>& sizes);

/// Body outline on a coarse grid (about 2 mm): mean HU above the threshold, opened so thin
/// attachments (a table shell, cables) fall off, holes filled, pieces smaller than a fifth of the
/// largest dropped. inside[i] for every CT voxel of `box`. False with `error`.
bool BodyOutline(vtkImageData* ct, const double spacing[3], const Box& box, const BoneSplitOptions& options,
                 std::vector<uint8_t>& inside, std::string& error);

/// Each bone (group) made solid on its own (so no gap between two bones is filled): closed with a
/// ball of `radiusMm`, holes filled in 3-D and slice by slice along every axis. Background voxels
/// claimed by exactly one bone join it; voxels two bones claim stay background. False with `error`.
bool SolidifyBones(std::vector<int32_t>& group, const Box& box, const double spacing[3], double radiusMm,
                   std::string& error);

/// The edge of each bone where the CT says it is: surface voxels below the local half maximum
/// between the bone's peak within `peakMm` and the soft tissue beside it are peeled, `layers`
/// passes (`fixedHU` > 0: a fixed edge instead); why: PeelEdgesOf in rpBoneMasks.cxx.
void PeelEdges(vtkImageData* ct, const double spacing[3], const Box& box, std::vector<int32_t>& group, double fixedHU,
               double lowerHU, double peakMm, int layers);

/// `op` on a 0/1 mask over `box`, in place, with a ball of `radius` voxels per axis (at least 1); a
/// closing keeps a safe border (the box's edge does not erode the mask). False with `error`.
bool MaskMorphology(std::vector<uint8_t>& mask, const Box& box, Morphology op, const int radius[3], std::string& error);

/// Distance to the bone surface (mm) inside the bone, 0 outside. False with `error`.
bool DistanceInsideBone(std::vector<uint8_t>& mask, const Box& box, const double spacing[3],
                        std::vector<float>& distance, std::string& error);

}  // namespace rp::bonesplit
