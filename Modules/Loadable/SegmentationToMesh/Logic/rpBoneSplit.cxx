#include "rpBoneSplit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include <itkBinaryBallStructuringElement.h>
#include <itkBinaryMorphologicalClosingImageFilter.h>
#include <itkBinaryMorphologicalOpeningImageFilter.h>
#include <itkImage.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkSMPTools.h>

#include "rpKneeBoneNames.h"
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

// A box of the CT (voxel index range) holding every bone voxel, and masks over it.
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

template <typename T>
void ThresholdVolume(const T* v, size_t n, double lower, double upper, std::vector<uint8_t>& mask) {
  mask.assign(n, 0);
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i) {
      const double x = static_cast<double>(v[i]);
      mask[static_cast<size_t>(i)] = x >= lower && x <= upper;
    }
  });
}

// Background reachable from the box border (6-connected) stays background; the rest is filled.
// With `sliceAxis` >= 0 the flood runs in each slice across that axis separately (2-D holes).
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
    vtkSMPTools::For(0, n[sliceAxis], [&](vtkIdType s0, vtkIdType s1) {
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

// 6-connected components of a mask: labels 1..N (0 = background), voxel count per label.
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

// Body outline on a coarse grid (about 2 mm): mean HU above the threshold, opened so thin
// attachments (a table shell, cables) fall off, holes filled, pieces smaller than a fifth of the
// largest dropped. inside[i] for every CT voxel of `box`.
template <typename T>
void BodyOutline(const T* ct, const int dims[3], const double spacing[3], const Box& box,
                 const BoneSplitOptions& options, std::vector<uint8_t>& inside) {
  int f[3], low[3];
  for (int a = 0; a < 3; ++a) {
    f[a] = std::max(1, static_cast<int>(std::lround(2.0 / spacing[a])));
    low[a] = (dims[a] + f[a] - 1) / f[a];
  }
  using Mask = itk::Image<unsigned char, 3>;
  auto body = Mask::New();
  Mask::RegionType region;
  for (unsigned a = 0; a < 3; ++a) region.SetSize(a, static_cast<itk::SizeValueType>(low[a]));
  body->SetRegions(region);
  body->Allocate();
  unsigned char* b = body->GetBufferPointer();
  vtkSMPTools::For(0, low[2], [&](vtkIdType k0, vtkIdType k1) {
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
  Mask::Pointer opened = body;
  const double lowSpacing = 2.0;
  const int radius = static_cast<int>(std::lround(options.BodyOpeningMm / lowSpacing));
  if (radius > 0) {
    using Ball = itk::BinaryBallStructuringElement<unsigned char, 3>;
    Ball ball;
    ball.SetRadius(static_cast<itk::SizeValueType>(radius));
    ball.CreateStructuringElement();
    auto open = itk::BinaryMorphologicalOpeningImageFilter<Mask, Mask, Ball>::New();
    open->SetInput(body);
    open->SetKernel(ball);
    open->SetForegroundValue(1);
    open->SetBackgroundValue(0);
    open->Update();
    opened = open->GetOutput();
  }
  Box lowBox;
  for (int a = 0; a < 3; ++a) lowBox.Size[a] = low[a];
  std::vector<uint8_t> lowMask(opened->GetBufferPointer(), opened->GetBufferPointer() + lowBox.Count());
  FillHoles(lowMask, lowBox, -1);
  std::vector<int32_t> labels;
  std::vector<long> sizes;
  Components(lowMask, lowBox, labels, sizes);
  const long largest = sizes.size() > 1 ? *std::max_element(sizes.begin() + 1, sizes.end()) : 0;
  inside.assign(box.Count(), 0);
  vtkSMPTools::For(0, box.Size[2], [&](vtkIdType k0, vtkIdType k1) {
    for (vtkIdType kk = k0; kk < k1; ++kk)
      for (int jj = 0; jj < box.Size[1]; ++jj)
        for (int ii = 0; ii < box.Size[0]; ++ii) {
          const int i = box.Lo[0] + ii, j = box.Lo[1] + jj, k = box.Lo[2] + static_cast<int>(kk);
          const int32_t l = labels[lowBox.Index(i / f[0], j / f[1], k / f[2])];
          inside[box.Index(ii, jj, static_cast<int>(kk))] = l > 0 && sizes[static_cast<size_t>(l)] * 5 >= largest;
        }
  });
}

// Each bone made solid on its own (so no gap between two bones is filled): closed with a ball
// of `radiusMm`, holes filled in 3-D and slice by slice along every axis. Background voxels
// claimed by exactly one bone join it; voxels two bones claim stay background.
void SolidifyBones(std::vector<int32_t>& group, const Box& box, const double spacing[3], double radiusMm) {
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
  using Mask = itk::Image<unsigned char, 3>;
  using Ball = itk::BinaryBallStructuringElement<unsigned char, 3>;
  Ball ball;
  Ball::SizeType ballSize;
  for (unsigned a = 0; a < 3; ++a) ballSize[a] = static_cast<itk::SizeValueType>(radius[a]);
  ball.SetRadius(ballSize);
  ball.CreateStructuringElement();
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
    auto image = Mask::New();
    Mask::RegionType region;
    for (unsigned a = 0; a < 3; ++a) region.SetSize(a, static_cast<itk::SizeValueType>(sub.Size[a]));
    image->SetRegions(region);
    image->GetPixelContainer()->SetImportPointer(mine.data(), mine.size(), false);
    auto close = itk::BinaryMorphologicalClosingImageFilter<Mask, Mask, Ball>::New();
    close->SetInput(image);
    close->SetKernel(ball);
    close->SetForegroundValue(1);
    close->SafeBorderOn();
    close->Update();
    std::vector<uint8_t> solid(close->GetOutput()->GetBufferPointer(), close->GetOutput()->GetBufferPointer() + sub.Count());
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
}

// The edge of each bone where the CT says it is: a surface voxel (a face neighbour outside the
// bone) is a partial-volume voxel mostly outside the bone when its HU is below the half maximum
// between the bone's local peak (the densest voxel of the same bone within `peakMm`) and the
// soft tissue beside it (its outside face neighbours); peeled, in `layers` passes. The threshold
// that finds bone (low, so a thin cortex is kept) is not where its edge is: a thick cortex
// (1500 HU) has its edge near 750 HU, a thin one whose partial-volume peak is 600 HU near 300 HU.
// `fixedHU` > 0 replaces the local half maximum by a fixed edge.
template <typename T>
void PeelEdges(const T* ct, const int dims[3], const double spacing[3], const Box& box, std::vector<int32_t>& group,
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

// Union-find over watershed regions.
struct Regions {
  std::vector<int32_t> Parent;
  std::vector<float> Depth;    // deepest distance (mm) in the region
  std::vector<int32_t> Seed;   // seed index + 1, 0 = none
  int32_t Add(float depth) {
    this->Parent.push_back(static_cast<int32_t>(this->Parent.size()));
    this->Depth.push_back(depth);
    this->Seed.push_back(0);
    return this->Parent.back();
  }
  int32_t Find(int32_t r) {
    while (this->Parent[static_cast<size_t>(r)] != r) {
      this->Parent[static_cast<size_t>(r)] = this->Parent[static_cast<size_t>(this->Parent[static_cast<size_t>(r)])];
      r = this->Parent[static_cast<size_t>(r)];
    }
    return r;
  }
  void Union(int32_t a, int32_t b) {  // b into a
    this->Parent[static_cast<size_t>(b)] = a;
    this->Depth[static_cast<size_t>(a)] = std::max(this->Depth[static_cast<size_t>(a)], this->Depth[static_cast<size_t>(b)]);
    if (!this->Seed[static_cast<size_t>(a)]) this->Seed[static_cast<size_t>(a)] = this->Seed[static_cast<size_t>(b)];
  }
};

// Watershed of the distance map from its deepest points down, merging regions as described in
// the header. `seedVoxels[s]` = box index where seed s sits (its basin's deepest point).
// Returns per-voxel group (root region id + 1, 0 = background) and the number of kept splits.
int Watershed(const std::vector<float>& distance, const std::vector<uint8_t>& mask, const Box& box,
              const BoneSplitOptions& options, const std::vector<size_t>& seedVoxels, const std::vector<int>& seedName,
              std::vector<int32_t>& group, std::vector<std::pair<int, int>>& seedConflicts) {
  std::vector<uint32_t> order;
  for (size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) order.push_back(static_cast<uint32_t>(i));
  // Equal distances (many on a voxel grid) in a fixed order: the order decides which basin a tied
  // voxel floods into, so it must not be left to the sort (VTK's TBB back-end orders ties unlike
  // its STDThread and Sequential ones: the two seeded lobes of rpBoneSplitTest's peanut came out
  // 6.36/5.36 ml on one, 6.39/5.32 on the others). Not by index either, which runs along x: a
  // bijective 32-bit mix of it (MurmurHash3's finalizer) keeps the order strict and scattered.
  auto mix = [](uint32_t h) {
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    return h ^ (h >> 16);
  };
  vtkSMPTools::Sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return distance[a] > distance[b] || (distance[a] == distance[b] && mix(a) < mix(b));
  });
  std::vector<int32_t> region(mask.size(), -1);
  std::map<size_t, int> seedAt;
  for (size_t s = 0; s < seedVoxels.size(); ++s) seedAt[seedVoxels[s]] = static_cast<int>(s);
  Regions regions;
  std::set<std::pair<int32_t, int32_t>> kept;  // region pairs kept apart (by root at the time)
  const int* n = box.Size;
  const size_t stride[3] = {1, static_cast<size_t>(n[0]), static_cast<size_t>(n[0]) * static_cast<size_t>(n[1])};
  auto sameName = [&](int32_t a, int32_t b) {
    const int sa = regions.Seed[static_cast<size_t>(a)], sb = regions.Seed[static_cast<size_t>(b)];
    if (!sa || !sb) return true;
    return seedName[static_cast<size_t>(sa - 1)] == seedName[static_cast<size_t>(sb - 1)];
  };
  std::vector<int32_t> roots;
  for (uint32_t idx : order) {
    const float d = distance[idx];
    const int c[3] = {static_cast<int>(idx % stride[1]), static_cast<int>((idx / stride[1]) % static_cast<size_t>(n[1])),
                      static_cast<int>(idx / stride[2])};
    // Processed neighbours' regions, the one of the deepest neighbour first.
    roots.clear();
    float best = -1;
    for (int a = 0; a < 3; ++a)
      for (int dir : {-1, 1}) {
        const int q = c[a] + dir;
        if (q < 0 || q >= n[a]) continue;
        const size_t qi = dir < 0 ? idx - stride[a] : idx + stride[a];
        if (region[qi] < 0) continue;
        const int32_t r = regions.Find(region[qi]);
        if (distance[qi] > best) {
          best = distance[qi];
          roots.insert(roots.begin(), r);
        } else {
          roots.push_back(r);
        }
      }
    int32_t mine;
    if (roots.empty()) {
      mine = regions.Add(d);
    } else {
      mine = roots.front();
      for (size_t t = 1; t < roots.size(); ++t) {
        const int32_t other = regions.Find(roots[t]);
        mine = regions.Find(mine);
        if (other == mine) continue;
        const double shallow = std::min(regions.Depth[static_cast<size_t>(mine)], regions.Depth[static_cast<size_t>(other)]);
        const bool neck = shallow - d >= options.MinDepthMm && d < options.NeckRatio * shallow;
        if (!neck && sameName(mine, other)) {
          regions.Union(mine, other);
        } else {
          kept.insert({std::min(mine, other), std::max(mine, other)});
        }
      }
      mine = regions.Find(mine);
    }
    region[idx] = mine;
    const auto seed = seedAt.find(idx);
    if (seed != seedAt.end()) {
      int32_t& s = regions.Seed[static_cast<size_t>(mine)];
      if (s && seedName[static_cast<size_t>(s - 1)] != seedName[static_cast<size_t>(seed->second)])
        seedConflicts.push_back({s - 1, seed->second});
      else
        s = seed->second + 1;
    }
  }
  group.assign(mask.size(), 0);
  for (size_t i = 0; i < mask.size(); ++i)
    if (region[i] >= 0) group[i] = regions.Find(region[i]) + 1;
  std::set<std::pair<int32_t, int32_t>> finalPairs;
  for (const auto& [a, b] : kept) {
    const int32_t ra = regions.Find(a), rb = regions.Find(b);
    if (ra != rb) finalPairs.insert({std::min(ra, rb), std::max(ra, rb)});
  }
  return static_cast<int>(finalPairs.size());
}

// From a voxel, up the distance map to a local maximum within the same mask (26-neighbours).
size_t ClimbToDeepest(const std::vector<float>& distance, const std::vector<uint8_t>& mask, const Box& box, size_t idx) {
  const int* n = box.Size;
  for (;;) {
    const int i = static_cast<int>(idx % static_cast<size_t>(n[0]));
    const int j = static_cast<int>((idx / static_cast<size_t>(n[0])) % static_cast<size_t>(n[1]));
    const int k = static_cast<int>(idx / (static_cast<size_t>(n[0]) * static_cast<size_t>(n[1])));
    size_t best = idx;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int q[3] = {i + di, j + dj, k + dk};
          if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n[0] || q[1] >= n[1] || q[2] >= n[2]) continue;
          const size_t qi = box.Index(q[0], q[1], q[2]);
          if (mask[qi] && distance[qi] > distance[best]) best = qi;
        }
    if (best == idx) return idx;
    idx = best;
  }
}

// The steps of SplitBones, in order; each returns false with `error` set when it cannot go on.

// 1. Threshold, crop to the bone (2 voxels of margin), close one-voxel gaps, fill holes.
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
bool KeepBonePieces(vtkImageData* image, const int dims[3], const double spacing[3], double voxelMl, const Box& box,
                    const BoneSplitOptions& options, std::vector<uint8_t>& mask, BoneSplitResult& result,
                    std::string& error) {
  std::vector<uint8_t> body;
  switch (image->GetScalarType()) {
    vtkTemplateMacro(BodyOutline(static_cast<const VTK_TT*>(image->GetScalarPointer()), dims, spacing, box, options,
                                 body));
  }
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

// 3. Distance to the bone surface (mm) inside the bone, 0 outside.
bool DistanceInsideBone(std::vector<uint8_t>& mask, const Box& box, const double spacing[3],
                        std::vector<float>& distance, std::string& error) {
  distance.assign(mask.size(), 0.0f);
  using Mask = itk::Image<unsigned char, 3>;
  auto itkMask = Mask::New();
  Mask::RegionType region;
  for (unsigned a = 0; a < 3; ++a) region.SetSize(a, static_cast<itk::SizeValueType>(box.Size[a]));
  itkMask->SetRegions(region);
  itkMask->GetPixelContainer()->SetImportPointer(mask.data(), mask.size(), false);
  const double itkSpacing[3] = {spacing[0], spacing[1], spacing[2]};
  itkMask->SetSpacing(itkSpacing);
  auto map = itk::SignedMaurerDistanceMapImageFilter<Mask, itk::Image<float, 3>>::New();
  map->SetInput(itkMask);
  map->SetInsideIsPositive(true);
  map->SetUseImageSpacing(true);
  map->SetSquaredDistance(false);
  map->SetBackgroundValue(0);
  try {
    map->Update();
  } catch (const itk::ExceptionObject& e) {
    error = std::string("distance map: ") + e.GetDescription();
    return false;
  }
  const float* d = map->GetOutput()->GetBufferPointer();
  for (size_t i = 0; i < mask.size(); ++i) distance[i] = mask[i] ? std::max(0.0f, d[i]) : 0.0f;
  return true;
}

// 4. Seeds: onto bone (the nearest bone voxel within 5 mm), then up to their basin's deepest
// point; seeds of one name share a name index (unnamed seeds are all distinct).
bool PlaceSeeds(vtkRPImageNode* ct, const BoneSplitOptions& options, const Box& box, const double spacing[3],
                const std::vector<uint8_t>& mask, const std::vector<float>& distance, std::vector<size_t>& seedVoxels,
                std::vector<int>& seedName, std::string& error) {
  std::vector<std::string> names;
  vtkNew<vtkMatrix4x4> rasToIJK;
  ct->GetRASToIJKMatrix(rasToIJK);
  for (size_t s = 0; s < options.Seeds.size(); ++s) {
    const auto& seed = options.Seeds[s];
    const double p[4] = {seed.RAS[0], seed.RAS[1], seed.RAS[2], 1};
    double ijk[4];
    rasToIJK->MultiplyPoint(p, ijk);
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = static_cast<int>(std::lround(ijk[a])) - box.Lo[a];
    const std::string label = "seed (" + std::to_string(seed.RAS[0]) + ", " + std::to_string(seed.RAS[1]) + ", " +
                              std::to_string(seed.RAS[2]) + ")" + (seed.Name.empty() ? "" : " '" + seed.Name + "'");
    size_t found = mask.size();
    double bestD2 = std::numeric_limits<double>::max();
    int reach[3];
    for (int a = 0; a < 3; ++a) reach[a] = static_cast<int>(std::ceil(5.0 / spacing[a]));
    for (int dk = -reach[2]; dk <= reach[2]; ++dk)
      for (int dj = -reach[1]; dj <= reach[1]; ++dj)
        for (int di = -reach[0]; di <= reach[0]; ++di) {
          const int q[3] = {c[0] + di, c[1] + dj, c[2] + dk};
          if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= box.Size[0] || q[1] >= box.Size[1] || q[2] >= box.Size[2])
            continue;
          const size_t qi = box.Index(q[0], q[1], q[2]);
          if (!mask[qi]) continue;
          const double d2 = std::pow(di * spacing[0], 2) + std::pow(dj * spacing[1], 2) + std::pow(dk * spacing[2], 2);
          if (d2 < bestD2 && d2 <= 25.0) bestD2 = d2, found = qi;
        }
    if (found == mask.size()) {
      error = label + " is not on bone (no bone voxel within 5 mm)";
      return false;
    }
    seedVoxels.push_back(ClimbToDeepest(distance, mask, box, found));
    int nameIndex = -1;
    if (!seed.Name.empty())
      for (size_t n = 0; n < names.size(); ++n)
        if (names[n] == seed.Name) nameIndex = static_cast<int>(n);
    if (nameIndex < 0) {
      nameIndex = static_cast<int>(names.size());
      names.push_back(seed.Name);
    }
    seedName.push_back(nameIndex);
  }
  return true;
}

// 5. Groups → bones: small groups (bumps of a bone) join the neighbour they touch most.
void MergeSmallGroups(std::vector<int32_t>& group, const Box& box, long minVoxels) {
  std::map<int32_t, long> groupSize;
  for (int32_t g : group)
    if (g) ++groupSize[g];
  for (bool changed = true; changed;) {
    changed = false;
    // Contacts of every small group with its neighbours, in one pass.
    std::map<int32_t, std::map<int32_t, long>> contact;
    const int lo[3] = {0, 0, 0}, hi[3] = {box.Size[0] - 1, box.Size[1] - 1, box.Size[2] - 1};
    for (size_t i = 0; i < group.size(); ++i) {
      const int32_t g = group[i];
      if (!g || groupSize[g] >= minVoxels) continue;
      ForFaceNeighbours(box, i, lo, hi, [&](size_t qi) {
        if (group[qi] && group[qi] != g) ++contact[g][group[qi]];
      });
    }
    std::map<int32_t, int32_t> into;
    for (const auto& [g, touching] : contact) {
      const int32_t target =
          std::max_element(touching.begin(), touching.end(), [](auto& x, auto& y) { return x.second < y.second; })->first;
      if (into.count(target)) continue;  // the target itself moves this round: next round
      into[g] = target;
    }
    for (int32_t& v : group) {
      const auto it = v ? into.find(v) : into.end();
      if (it != into.end()) v = it->second;
    }
    for (const auto& [g, target] : into) {
      groupSize[target] += groupSize[g];
      groupSize[g] = 0;
      changed = true;
    }
  }
}

// 6. Bones in order of size (at most 250), labelled 1, 2, ... in that order (`labelOf`).
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

// 7. The labelmap on the CT's grid, and each bone's centroid and bounds.
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

// 8. Pieces given one name (condyles cut by the field of view, seeds with the same name) are one
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

// 9. Unnamed bones become "Bone N", IDs unique; the segmentation gets the labelmap and a segment per bone.
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
  if (!KeepBonePieces(image, dims, spacing, voxelMl, box, options, mask, result, error)) return false;

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
  SolidifyBones(group, box, spacing, options.FillRadiusMm);
  if (options.EdgeLayers > 0) {
    switch (image->GetScalarType()) {
      vtkTemplateMacro(PeelEdges(static_cast<const VTK_TT*>(image->GetScalarPointer()), dims, spacing, box, group,
                                 options.EdgeHU, options.LowerHU, options.EdgePeakMm, options.EdgeLayers));
    }
  }
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
