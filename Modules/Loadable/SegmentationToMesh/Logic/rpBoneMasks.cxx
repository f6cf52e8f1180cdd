#include "rpBoneMasks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <vtkImageData.h>

#include "rpParallelFor.h"
#include "rpSegmentationItkEntries.h"

namespace rp::bonesplit {

void FillHoles(std::vector<uint8_t>& mask, const Box& box, int sliceAxis) {
  std::vector<uint8_t> outside(mask.size(), 0);
  const int* n = box.Size;
  auto flood = [&](std::vector<size_t>& stack, const int lo[3], const int hi[3]) {
    while (!stack.empty()) {
      const size_t idx = stack.back();
      stack.pop_back();
      ForFaceNeighbours(box, idx, lo, hi, [&](size_t qi) {
        if (mask[qi] || outside[qi]) return;
        outside[qi] = 1;
        stack.push_back(qi);
      });
    }
  };
  auto seedBorder = [&](const int lo[3], const int hi[3], std::vector<size_t>& stack) {
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const int p[3] = {i, j, k};
          bool border = false;
          for (int a = 0; a < 3; ++a) border = border || (lo[a] != hi[a] && (p[a] == lo[a] || p[a] == hi[a]));
          if (!border) continue;
          const size_t idx = box.Index(i, j, k);
          if (mask[idx] || outside[idx]) continue;
          outside[idx] = 1;
          stack.push_back(idx);
        }
  };
  if (sliceAxis < 0) {
    const int lo[3] = {0, 0, 0}, hi[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
    std::vector<size_t> stack;
    seedBorder(lo, hi, stack);
    flood(stack, lo, hi);
  } else {
    ParallelFor(0, n[sliceAxis], [&](vtkIdType s0, vtkIdType s1) {
      std::vector<size_t> stack;
      for (vtkIdType s = s0; s < s1; ++s) {
        int lo[3] = {0, 0, 0}, hi[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
        lo[sliceAxis] = hi[sliceAxis] = static_cast<int>(s);
        seedBorder(lo, hi, stack);
        flood(stack, lo, hi);
      }
    });
  }
  for (size_t i = 0; i < mask.size(); ++i) mask[i] = outside[i] ? 0 : 1;
}

int Components(const std::vector<uint8_t>& mask, const Box& box, std::vector<int32_t>& labels,
               std::vector<long>& sizes) {
  labels.assign(mask.size(), 0);
  sizes.assign(1, 0);
  std::vector<size_t> stack;
  const int lo[3] = {0, 0, 0}, hi[3] = {box.Size[0] - 1, box.Size[1] - 1, box.Size[2] - 1};
  int next = 0;
  for (size_t start = 0; start < mask.size(); ++start) {
    if (!mask[start] || labels[start]) continue;
    ++next;
    long count = 0;
    labels[start] = next;
    stack.push_back(start);
    while (!stack.empty()) {
      const size_t idx = stack.back();
      stack.pop_back();
      ++count;
      ForFaceNeighbours(box, idx, lo, hi, [&](size_t qi) {
        if (!mask[qi] || labels[qi]) return;
        labels[qi] = next;
        stack.push_back(qi);
      });
    }
    sizes.push_back(count);
  }
  return next;
}

namespace {

// Body outline on a coarse grid (about 2 mm): mean HU above the threshold, opened so thin
// attachments (a table shell, cables) fall off, holes filled, pieces smaller than a fifth of the
// largest dropped. inside[i] for every CT voxel of `box`.
template <typename T>
bool BodyOutlineOf(const T* ct, const int dims[3], const double spacing[3], const Box& box,
                   const BoneSplitOptions& options, std::vector<uint8_t>& inside, std::string& error) {
  int f[3], low[3];
  for (int a = 0; a < 3; ++a) {
    f[a] = std::max(1, static_cast<int>(std::lround(2.0 / spacing[a])));
    low[a] = (dims[a] + f[a] - 1) / f[a];
  }
  Box lowBox;
  for (int a = 0; a < 3; ++a) lowBox.Size[a] = low[a];
  std::vector<uint8_t> lowMask(lowBox.Count());
  uint8_t* b = lowMask.data();
  ParallelFor(0, low[2], [&](vtkIdType k0, vtkIdType k1) {
    for (vtkIdType lk = k0; lk < k1; ++lk)
      for (int lj = 0; lj < low[1]; ++lj)
        for (int li = 0; li < low[0]; ++li) {
          double sum = 0;
          int count = 0;
          for (int k = static_cast<int>(lk) * f[2]; k < std::min(dims[2], static_cast<int>(lk + 1) * f[2]); ++k)
            for (int j = lj * f[1]; j < std::min(dims[1], (lj + 1) * f[1]); ++j)
              for (int i = li * f[0]; i < std::min(dims[0], (li + 1) * f[0]); ++i, ++count)
                sum += static_cast<double>(ct[(static_cast<size_t>(k) * dims[1] + j) * dims[0] + i]);
          b[(static_cast<size_t>(lk) * low[1] + lj) * low[0] + li] = count && sum / count > options.BodyLowerHU;
        }
  });
  const double lowSpacing = 2.0;
  const int radius = static_cast<int>(std::lround(options.BodyOpeningMm / lowSpacing));
  const int ball[3] = {radius, radius, radius};
  if (radius > 0 && !MaskMorphology(lowMask, lowBox, Morphology::Opening, ball, error)) return false;
  FillHoles(lowMask, lowBox, -1);
  std::vector<int32_t> labels;
  std::vector<long> sizes;
  Components(lowMask, lowBox, labels, sizes);
  const long largest = sizes.size() > 1 ? *std::max_element(sizes.begin() + 1, sizes.end()) : 0;
  inside.assign(box.Count(), 0);
  ParallelFor(0, box.Size[2], [&](vtkIdType k0, vtkIdType k1) {
    for (vtkIdType kk = k0; kk < k1; ++kk)
      for (int jj = 0; jj < box.Size[1]; ++jj)
        for (int ii = 0; ii < box.Size[0]; ++ii) {
          const int i = box.Lo[0] + ii, j = box.Lo[1] + jj, k = box.Lo[2] + static_cast<int>(kk);
          const int32_t l = labels[lowBox.Index(i / f[0], j / f[1], k / f[2])];
          inside[box.Index(ii, jj, static_cast<int>(kk))] = l > 0 && sizes[static_cast<size_t>(l)] * 5 >= largest;
        }
  });
  return true;
}

// The edge of each bone where the CT says it is: a surface voxel (a face neighbour outside the
// bone) is a partial-volume voxel mostly outside the bone when its HU is below the half maximum
// between the bone's local peak (the densest voxel of the same bone within `peakMm`) and the
// soft tissue beside it (its outside face neighbours); peeled, in `layers` passes. The threshold
// that finds bone (low, so a thin cortex is kept) is not where its edge is: a thick cortex
// (1500 HU) has its edge near 750 HU, a thin one whose partial-volume peak is 600 HU near 300 HU.
// `fixedHU` > 0 replaces the local half maximum by a fixed edge.
template <typename T>
void PeelEdgesOf(const T* ct, const int dims[3], const double spacing[3], const Box& box, std::vector<int32_t>& group,
                 double fixedHU, double lowerHU, double peakMm, int layers) {
  const int* n = box.Size;
  auto huAt = [&](int i, int j, int k) {
    return static_cast<double>(
        ct[(static_cast<size_t>(box.Lo[2] + k) * dims[1] + box.Lo[1] + j) * dims[0] + box.Lo[0] + i]);
  };
  int reach[3];
  for (int a = 0; a < 3; ++a) reach[a] = std::max(1, static_cast<int>(std::lround(peakMm / spacing[a])));
  for (int pass = 0; pass < layers; ++pass) {
    std::vector<size_t> peel;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const size_t idx = box.Index(i, j, k);
          const int32_t g = group[idx];
          if (!g) continue;
          const double hu = huAt(i, j, k);
          const int c[3] = {i, j, k};
          bool surface = false;
          double outsideSum = 0;
          int outside = 0;
          for (int a = 0; a < 3; ++a)
            for (int d : {-1, 1}) {
              int q[3] = {c[0], c[1], c[2]};
              q[a] += d;
              if (q[a] < 0 || q[a] >= n[a]) continue;  // the field of view's edge is not the bone's
              const int32_t other = group[box.Index(q[0], q[1], q[2])];
              if (other == g) continue;
              surface = true;
              if (!other) outsideSum += huAt(q[0], q[1], q[2]), ++outside;
            }
          if (!surface) continue;
          double edge = fixedHU;
          if (!(fixedHU > 0)) {
            double peak = hu;
            for (int dk = -reach[2]; dk <= reach[2]; ++dk)
              for (int dj = -reach[1]; dj <= reach[1]; ++dj)
                for (int di = -reach[0]; di <= reach[0]; ++di) {
                  const int q[3] = {i + di, j + dj, k + dk};
                  if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n[0] || q[1] >= n[1] || q[2] >= n[2]) continue;
                  if (group[box.Index(q[0], q[1], q[2])] == g) peak = std::max(peak, huAt(q[0], q[1], q[2]));
                }
            // Soft tissue beside the bone; never above the bone threshold (a neighbour bone's
            // partial volume is not soft tissue).
            const double background = outside ? std::min(outsideSum / outside, lowerHU) : lowerHU;
            // Never below the threshold that found the bone.
            edge = std::max(lowerHU, 0.5 * (peak + background));
          }
          if (hu < edge) peel.push_back(idx);
        }
    for (size_t idx : peel) group[idx] = 0;
  }
}

}  // namespace

bool BodyOutline(vtkImageData* ct, const double spacing[3], const Box& box, const BoneSplitOptions& options,
                 std::vector<uint8_t>& inside, std::string& error) {
  int dims[3];
  ct->GetDimensions(dims);
  switch (ct->GetScalarType()) {
    vtkTemplateMacro(return BodyOutlineOf(static_cast<const VTK_TT*>(ct->GetScalarPointer()), dims, spacing, box,
                                          options, inside, error));
  }
  error = "the CT's voxel type is not supported";
  return false;
}

bool SolidifyBones(std::vector<int32_t>& group, const Box& box, const double spacing[3], double radiusMm,
                   std::string& error) {
  std::map<int32_t, std::array<int, 6>> extents;
  const int* n = box.Size;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const int32_t g = group[box.Index(i, j, k)];
        if (!g) continue;
        auto it = extents.find(g);
        if (it == extents.end()) it = extents.insert({g, {i, i, j, j, k, k}}).first;
        auto& e = it->second;
        e[0] = std::min(e[0], i), e[1] = std::max(e[1], i), e[2] = std::min(e[2], j), e[3] = std::max(e[3], j);
        e[4] = std::min(e[4], k), e[5] = std::max(e[5], k);
      }
  int radius[3];
  for (int a = 0; a < 3; ++a) radius[a] = std::max(1, static_cast<int>(std::lround(radiusMm / spacing[a])));
  std::vector<int32_t> claim(group.size(), 0);  // bone, or -1 when two bones claim the voxel
  for (const auto& [g, e] : extents) {
    Box sub;
    for (int a = 0; a < 3; ++a) {
      sub.Lo[a] = std::max(0, e[2 * a] - radius[a] - 1);
      sub.Size[a] = std::min(n[a] - 1, e[2 * a + 1] + radius[a] + 1) - sub.Lo[a] + 1;
    }
    std::vector<uint8_t> mine(sub.Count());
    for (int k = 0; k < sub.Size[2]; ++k)
      for (int j = 0; j < sub.Size[1]; ++j)
        for (int i = 0; i < sub.Size[0]; ++i)
          mine[sub.Index(i, j, k)] = group[box.Index(sub.Lo[0] + i, sub.Lo[1] + j, sub.Lo[2] + k)] == g;
    std::vector<uint8_t> solid = mine;
    if (!MaskMorphology(solid, sub, Morphology::Closing, radius, error)) return false;
    for (size_t i = 0; i < solid.size(); ++i) solid[i] |= mine[i];
    FillHoles(solid, sub, -1);
    for (int axis = 0; axis < 3; ++axis) FillHoles(solid, sub, axis);
    for (int k = 0; k < sub.Size[2]; ++k)
      for (int j = 0; j < sub.Size[1]; ++j)
        for (int i = 0; i < sub.Size[0]; ++i) {
          if (!solid[sub.Index(i, j, k)]) continue;
          const size_t idx = box.Index(sub.Lo[0] + i, sub.Lo[1] + j, sub.Lo[2] + k);
          if (group[idx]) continue;
          claim[idx] = claim[idx] == 0 || claim[idx] == g ? g : -1;
        }
  }
  for (size_t i = 0; i < group.size(); ++i)
    if (claim[i] > 0) group[i] = claim[i];
  return true;
}

void PeelEdges(vtkImageData* ct, const double spacing[3], const Box& box, std::vector<int32_t>& group, double fixedHU,
               double lowerHU, double peakMm, int layers) {
  int dims[3];
  ct->GetDimensions(dims);
  switch (ct->GetScalarType()) {
    vtkTemplateMacro(PeelEdgesOf(static_cast<const VTK_TT*>(ct->GetScalarPointer()), dims, spacing, box, group, fixedHU,
                                 lowerHU, peakMm, layers));
  }
}

bool MaskMorphology(std::vector<uint8_t>& mask, const Box& box, Morphology op, const int radius[3], std::string& error) {
  return segmentationitk::Call<segmentationitk::MaskMorphologyFunction>(segmentationitk::MaskMorphologyEntry, error,
                                                                        mask, box, op, radius, error);
}

bool DistanceInsideBone(std::vector<uint8_t>& mask, const Box& box, const double spacing[3],
                        std::vector<float>& distance, std::string& error) {
  return segmentationitk::Call<segmentationitk::DistanceInsideBoneFunction>(
      segmentationitk::DistanceInsideBoneEntry, error, mask, box, spacing, distance, error);
}

}  // namespace rp::bonesplit
