#include "rpBoneWatershed.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSMPTools.h>

#include "vtkRPImageNode.h"

namespace rp::bonesplit {
namespace {

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

}  // namespace

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

}  // namespace rp::bonesplit
