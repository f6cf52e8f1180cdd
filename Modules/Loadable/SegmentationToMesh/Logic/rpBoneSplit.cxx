#include "rpBoneSplit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpBoneMasks.h"
#include "rpBoneWatershed.h"
#include "rpKneeBoneNames.h"
#include "rpParallelFor.h"
#include "vtkRPImageNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

bool ParseBoneSeed(const std::string& text, BoneSeed& seed, std::string& error) {
  const auto colon = text.find(':');
  const std::string point = text.substr(0, colon);
  seed.Name = colon == std::string::npos ? "" : text.substr(colon + 1);
  std::stringstream in(point);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (n >= 3 || part.empty() || !end || *end != '\0' || !std::isfinite(v)) {
      error = "seed '" + text + "': expected R,A,S or R,A,S:name (RAS mm)";
      return false;
    }
    seed.RAS[static_cast<size_t>(n++)] = v;
  }
  if (n != 3) {
    error = "seed '" + text + "': expected R,A,S or R,A,S:name (RAS mm)";
    return false;
  }
  return true;
}

namespace {

using Clock = std::chrono::steady_clock;
using namespace bonesplit;

template <typename T>
void ThresholdVolume(const T* v, size_t n, double lower, double upper, std::vector<uint8_t>& mask) {
  mask.assign(n, 0);
  ParallelFor(0, static_cast<vtkIdType>(n), [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i) {
      const double x = static_cast<double>(v[i]);
      mask[static_cast<size_t>(i)] = x >= lower && x <= upper;
    }
  });
}

// The steps of SplitBones of their own (the others: rpBoneMasks.h, rpBoneWatershed.h), in order; each returns false with `error` set when it cannot go on.

// 1. Threshold, crop to the bone (2 voxels of margin).
bool ThresholdAndCrop(vtkImageData* image, const int dims[3], const BoneSplitOptions& options, Box& box,
                      std::vector<uint8_t>& mask, std::string& error) {
  std::vector<uint8_t> full;
  switch (image->GetScalarType()) {
    vtkTemplateMacro(ThresholdVolume(static_cast<const VTK_TT*>(image->GetScalarPointer()),
                                     static_cast<size_t>(image->GetNumberOfPoints()), options.LowerHU, options.UpperHU,
                                     full));
  }
  int lo[3] = {dims[0], dims[1], dims[2]}, hi[3] = {-1, -1, -1};
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j) {
      const uint8_t* row = full.data() + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
      for (int i = 0; i < dims[0]; ++i)
        if (row[i]) lo[0] = std::min(lo[0], i), hi[0] = std::max(hi[0], i), lo[1] = std::min(lo[1], j),
                    hi[1] = std::max(hi[1], j), lo[2] = std::min(lo[2], k), hi[2] = std::max(hi[2], k);
    }
  if (hi[0] < 0) {
    error = "no voxel of the CT lies in the bone range [" + std::to_string(options.LowerHU) + ", " +
            std::to_string(options.UpperHU) + "] HU";
    return false;
  }
  for (int a = 0; a < 3; ++a) {
    box.Lo[a] = std::max(0, lo[a] - 2);
    box.Size[a] = std::min(dims[a] - 1, hi[a] + 2) - box.Lo[a] + 1;
  }
  mask.assign(box.Count(), 0);
  for (int k = 0; k < box.Size[2]; ++k)
    for (int j = 0; j < box.Size[1]; ++j)
      std::copy_n(full.data() + (static_cast<size_t>(box.Lo[2] + k) * dims[1] + box.Lo[1] + j) * dims[0] + box.Lo[0],
                  box.Size[0], mask.data() + box.Index(0, j, k));
  return true;
}

// 2. Pieces: drop those outside the body outline and specks.
bool KeepBonePieces(vtkImageData* image, const double spacing[3], double voxelMl, const Box& box,
                    const BoneSplitOptions& options, std::vector<uint8_t>& mask, BoneSplitResult& result,
                    std::string& error) {
  std::vector<uint8_t> body;
  if (!BodyOutline(image, spacing, box, options, body, error)) return false;
  std::vector<int32_t> pieces;
  std::vector<long> sizes;
  const int pieceCount = Components(mask, box, pieces, sizes);
  std::vector<long> insideCount(static_cast<size_t>(pieceCount) + 1, 0);
  for (size_t i = 0; i < pieces.size(); ++i)
    if (pieces[i] && body[i]) ++insideCount[static_cast<size_t>(pieces[i])];
  std::vector<uint8_t> keep(static_cast<size_t>(pieceCount) + 1, 0);
  for (int p = 1; p <= pieceCount; ++p) {
    const double ml = static_cast<double>(sizes[static_cast<size_t>(p)]) * voxelMl;
    if (ml < options.MinBoneMl) {
      ++result.DroppedSpecks, result.DroppedSpecksMl += ml;
    } else if (2 * insideCount[static_cast<size_t>(p)] < sizes[static_cast<size_t>(p)]) {
      ++result.DroppedOutsideBody, result.DroppedOutsideBodyMl += ml;
    } else {
      keep[static_cast<size_t>(p)] = 1;
    }
  }
  std::vector<uint8_t>().swap(body);
  long kept = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    mask[i] = pieces[i] && keep[static_cast<size_t>(pieces[i])];
    kept += mask[i];
  }
  result.ThresholdVoxels = kept;
  if (kept == 0) {
    error = "no bone left after dropping specks (< " + std::to_string(options.MinBoneMl) + " ml) and pieces outside the body outline";
    return false;
  }
  return true;
}

// 3. Bones in order of size (at most 250), labelled 1, 2, ... in that order (`labelOf`).
std::vector<BoneInfo> BonesBySize(const std::vector<int32_t>& group, double voxelMl, std::map<int32_t, int>& labelOf,
                                  std::vector<std::string>& notes) {
  std::map<int32_t, long> groupSize;
  for (int32_t g : group)
    if (g) ++groupSize[g];
  std::vector<std::pair<long, int32_t>> bySize;
  for (const auto& [g, count] : groupSize)
    if (count > 0) bySize.push_back({count, g});
  std::sort(bySize.rbegin(), bySize.rend());
  if (bySize.size() > 250) {
    notes.push_back(std::to_string(bySize.size() - 250) + " smallest bones dropped (at most 250 segments)");
    bySize.resize(250);
  }
  std::vector<BoneInfo> bones(bySize.size());
  for (size_t b = 0; b < bySize.size(); ++b) {
    labelOf[bySize[b].second] = static_cast<int>(b) + 1;
    bones[b].LabelValue = static_cast<int>(b) + 1;
    bones[b].Voxels = bySize[b].first;
    bones[b].VolumeMl = static_cast<double>(bySize[b].first) * voxelMl;
    for (int a = 0; a < 3; ++a) bones[b].BoundsRAS[2 * a] = 1e300, bones[b].BoundsRAS[2 * a + 1] = -1e300;
  }
  return bones;
}

// 4. The labelmap on the CT's grid, and each bone's centroid and bounds.
vtkSmartPointer<vtkImageData> BoneLabelmap(vtkRPImageNode* ct, const int dims[3], const Box& box,
                                           const std::vector<int32_t>& group, const std::map<int32_t, int>& labelOf,
                                           std::vector<BoneInfo>& bones) {
  std::vector<std::array<double, 3>> sums(bones.size(), {0, 0, 0});
  auto labels = vtkSmartPointer<vtkImageData>::New();
  labels->SetDimensions(dims);
  labels->AllocateScalars(bones.size() < 256 ? VTK_UNSIGNED_CHAR : VTK_UNSIGNED_SHORT, 1);
  labels->GetPointData()->GetScalars()->Fill(0);
  vtkMatrix4x4* m = ct->GetIJKToRASMatrix();
  for (int k = 0; k < box.Size[2]; ++k)
    for (int j = 0; j < box.Size[1]; ++j)
      for (int i = 0; i < box.Size[0]; ++i) {
        const int32_t g = group[box.Index(i, j, k)];
        if (!g) continue;
        const auto it = labelOf.find(g);
        if (it == labelOf.end()) continue;
        const int I = box.Lo[0] + i, J = box.Lo[1] + j, K = box.Lo[2] + k;
        labels->SetScalarComponentFromDouble(I, J, K, 0, it->second);
        BoneInfo& bone = bones[static_cast<size_t>(it->second - 1)];
        auto& sum = sums[static_cast<size_t>(it->second - 1)];
        for (int r = 0; r < 3; ++r) {
          const double x = m->GetElement(r, 0) * I + m->GetElement(r, 1) * J + m->GetElement(r, 2) * K + m->GetElement(r, 3);
          sum[static_cast<size_t>(r)] += x;
          bone.BoundsRAS[2 * r] = std::min(bone.BoundsRAS[2 * r], x);
          bone.BoundsRAS[2 * r + 1] = std::max(bone.BoundsRAS[2 * r + 1], x);
        }
      }
  for (size_t b = 0; b < bones.size(); ++b)
    for (int r = 0; r < 3; ++r) bones[b].CentroidRAS[r] = sums[b][static_cast<size_t>(r)] / static_cast<double>(bones[b].Voxels);
  return labels;
}

// 5. Pieces given one name (condyles cut by the field of view, seeds with the same name) are one
// bone: one segment, the largest piece's label.
void MergeSameNamedBones(std::vector<BoneInfo>& bones, vtkImageData* labels) {
  std::map<std::string, size_t> first;
  std::vector<int> relabel(bones.size() + 1, 0);
  std::vector<BoneInfo> merged;
  for (size_t b = 0; b < bones.size(); ++b) {
    BoneInfo& bone = bones[b];
    relabel[static_cast<size_t>(bone.LabelValue)] = bone.LabelValue;
    const auto it = bone.Name.empty() ? first.end() : first.find(bone.Name);
    if (it == first.end()) {
      if (!bone.Name.empty()) first[bone.Name] = merged.size();
      merged.push_back(bone);
      continue;
    }
    BoneInfo& into = merged[it->second];
    relabel[static_cast<size_t>(bone.LabelValue)] = into.LabelValue;
    const double total = static_cast<double>(into.Voxels + bone.Voxels);
    for (int a = 0; a < 3; ++a) {
      into.CentroidRAS[a] = (into.CentroidRAS[a] * into.Voxels + bone.CentroidRAS[a] * bone.Voxels) / total;
      into.BoundsRAS[2 * a] = std::min(into.BoundsRAS[2 * a], bone.BoundsRAS[2 * a]);
      into.BoundsRAS[2 * a + 1] = std::max(into.BoundsRAS[2 * a + 1], bone.BoundsRAS[2 * a + 1]);
    }
    into.Voxels += bone.Voxels;
    into.VolumeMl += bone.VolumeMl;
  }
  if (merged.size() != bones.size()) {
    vtkDataArray* scalars = labels->GetPointData()->GetScalars();
    for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i) {
      const int v = static_cast<int>(scalars->GetTuple1(i));
      if (v && relabel[static_cast<size_t>(v)] != v) scalars->SetTuple1(i, relabel[static_cast<size_t>(v)]);
    }
    bones = merged;
  }
}

// 6. Unnamed bones become "Bone N", IDs unique; the segmentation gets the labelmap and a segment per bone.
void WriteBones(vtkRPImageNode* ct, vtkImageData* labels, const BoneSplitOptions& options,
                std::vector<BoneInfo>& bones, vtkRPSegmentationNode* segmentation) {
  int unnamed = 0;
  std::set<std::string> used;
  for (BoneInfo& bone : bones) {
    if (bone.Name.empty()) bone.Name = "Bone " + std::to_string(++unnamed);
    bone.ID = bone.Name;
    for (int n = 2; used.count(bone.ID); ++n) bone.ID = bone.Name + " " + std::to_string(n);
    used.insert(bone.ID);
  }
  const int previous = segmentation->StartModify();
  segmentation->RemoveAllSegments();
  segmentation->SetImageData(labels);
  segmentation->SetIJKToRASMatrix(ct->GetIJKToRASMatrix());
  for (const BoneInfo& bone : bones) {
    vtkRPSegmentationNode::Segment s;
    s.ID = bone.ID;
    s.Name = bone.ID;
    s.LabelValue = bone.LabelValue;
    s.TissueClass = options.TissueClass;
    const auto color = BoneColor(bone.Name, bone.LabelValue);
    for (int c = 0; c < 3; ++c) s.Color[c] = color[static_cast<size_t>(c)];
    segmentation->SetSegment(s);
  }
  segmentation->Modified();
  segmentation->EndModify(previous);
}

}  // namespace

bool SplitBones(vtkRPImageNode* ct, vtkRPSegmentationNode* segmentation, const BoneSplitOptions& options,
                BoneSplitResult& result, std::string& error, const ProgressCallback& progress) {
  const auto t0 = Clock::now();
  result = BoneSplitResult();
  vtkImageData* image = ct ? ct->GetImageData() : nullptr;
  if (!image || !image->GetPointData()->GetScalars() || image->GetNumberOfPoints() == 0 ||
      image->GetNumberOfScalarComponents() != 1) {
    error = "the CT has no image data (one value per voxel)";
    return false;
  }
  if (!segmentation) {
    error = "no segmentation given";
    return false;
  }
  if (!(options.LowerHU <= options.UpperHU) || !(options.NeckRatio > 0) || options.MinBoneMl < 0) {
    error = "invalid bone split options (lower <= upper HU, neck ratio > 0, minimum volume >= 0)";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  double spacing[3];
  ct->GetSpacing(spacing);
  const double voxelMl = spacing[0] * spacing[1] * spacing[2] / 1000.0;
  auto report = [&](double f, const std::string& m) {
    if (progress) progress(f, m);
  };

  report(0.0, "thresholding");
  Box box;
  std::vector<uint8_t> mask;
  if (!ThresholdAndCrop(image, dims, options, box, mask, error)) return false;
  report(0.1, "filling holes");
  FillHoles(mask, box, -1);
  // Cut shafts are open at the volume border and a thin cortex lets marrow reach the outside in
  // some slices: fill slice by slice along every axis, twice.
  for (int round = 0; round < 2; ++round)
    for (int axis = 0; axis < 3; ++axis) FillHoles(mask, box, axis);
  report(0.25, "body outline");
  if (!KeepBonePieces(image, spacing, voxelMl, box, options, mask, result, error)) return false;

  // The distance to the bone surface and the watershed split.
  report(0.4, "distance map");
  std::vector<float> distance;
  std::vector<size_t> seedVoxels;
  std::vector<int> seedName;
  if (!DistanceInsideBone(mask, box, spacing, distance, error) ||
      !PlaceSeeds(ct, options, box, spacing, mask, distance, seedVoxels, seedName, error))
    return false;
  report(0.55, "splitting touching bones");
  std::vector<int32_t> group;
  std::vector<std::pair<int, int>> conflicts;
  result.Splits = Watershed(distance, mask, box, options, seedVoxels, seedName, group, conflicts);
  for (const auto& [a, b] : conflicts)
    result.Notes.push_back("seeds " + std::to_string(a + 1) + " and " + std::to_string(b + 1) +
                           " lead to the same deepest point: they name one bone (move one into the other bone)");

  report(0.8, "naming bones");
  MergeSmallGroups(group, box, std::max(1L, static_cast<long>(std::ceil(options.MinBoneMl / voxelMl))));
  report(0.85, "filling bones");
  if (!SolidifyBones(group, box, spacing, options.FillRadiusMm, error)) return false;
  if (options.EdgeLayers > 0)
    PeelEdges(image, spacing, box, group, options.EdgeHU, options.LowerHU, options.EdgePeakMm, options.EdgeLayers);
  std::map<int32_t, int> labelOf;
  std::vector<BoneInfo> bones = BonesBySize(group, voxelMl, labelOf, result.Notes);
  // Seed names (a seed's group is the group of its voxel).
  for (size_t s = 0; s < seedVoxels.size(); ++s) {
    const auto it = labelOf.find(group[seedVoxels[s]]);
    if (it == labelOf.end() || options.Seeds[s].Name.empty()) continue;
    BoneInfo& bone = bones[static_cast<size_t>(it->second - 1)];
    if (!bone.Name.empty() && bone.Name != options.Seeds[s].Name) continue;  // noted above
    bone.Name = options.Seeds[s].Name;
    bone.NamedBy = "seed";
  }
  vtkSmartPointer<vtkImageData> labels = BoneLabelmap(ct, dims, box, group, labelOf, bones);
  double ctBounds[6];
  ct->GetRASBounds(ctBounds);
  if (options.NameKneeBones) NameKneeBones(bones, ctBounds);
  MergeSameNamedBones(bones, labels);
  WriteBones(ct, labels, options, bones, segmentation);
  result.Bones = bones;
  result.Seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  report(1.0, "done");
  return true;
}

}  // namespace rp
