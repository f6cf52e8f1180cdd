#include "rpDrillAnalytic.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace rp {

double BoxSignedDistance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = (lo + hi) * 0.5, half = (hi - lo) * 0.5;
  const Vec3 q{std::fabs(p.x - c.x) - half.x, std::fabs(p.y - c.y) - half.y, std::fabs(p.z - c.z) - half.z};
  const Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return Norm(outside) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

AnalyticBone BlockBone(const Vec3& lo, const Vec3& hi, uint8_t cortical, double shell, uint8_t trabecular) {
  AnalyticBone bone;
  bone.Lo = lo;
  bone.Hi = hi;
  bone.SignedDistance = [lo, hi](const Vec3& p) { return BoxSignedDistance(p, lo, hi); };
  if (shell > 0 && trabecular > 0) {
    bone.Material = [lo, hi, shell, cortical, trabecular](const Vec3& p) {
      return BoxSignedDistance(p, lo, hi) < -shell ? trabecular : cortical;
    };
  } else {
    bone.Material = [cortical](const Vec3&) { return cortical; };
  }
  return bone;
}

bool BuildAnalyticBone(const AnalyticBone& bone, double spacing, const std::vector<Material>& materials,
                       DrillVolume& volume, std::string& error) {
  if (!bone.SignedDistance) {
    error = "analytic bone: no signed distance";
    return false;
  }
  if (!(bone.Lo.x < bone.Hi.x && bone.Lo.y < bone.Hi.y && bone.Lo.z < bone.Hi.z)) {
    error = "analytic bone: empty bounds";
    return false;
  }
  // Margin: the ramp (one voxel) plus two empty voxels so the surface closes.
  const double margin = 3 * spacing;
  DrillGrid grid;
  grid.Spacing = spacing;
  grid.Origin = bone.Lo - Vec3{margin, margin, margin};
  for (int a = 0; a < 3; ++a)
    grid.Dimensions[a] = static_cast<int>(std::ceil((bone.Hi[a] - bone.Lo[a] + 2 * margin) / spacing)) + 1;
  if (!volume.Initialize(grid, materials, error)) return false;
  const int E = DrillVolume::BlockEdge;
  const double halfDiagonal = std::sqrt(3.0) * 0.5 * E * spacing;
  for (int bk = 0; bk < volume.BlockDimensions()[2]; ++bk)
    for (int bj = 0; bj < volume.BlockDimensions()[1]; ++bj)
      for (int bi = 0; bi < volume.BlockDimensions()[0]; ++bi) {
        // Skip blocks far outside the bone (the signed distance is 1-Lipschitz).
        const Vec3 centre = grid.Center(bi * E, bj * E, bk * E) + Vec3{1, 1, 1} * (0.5 * (E - 1) * spacing);
        const bool mayProtect = static_cast<bool>(bone.Protected);
        if (!mayProtect && bone.SignedDistance(centre) > halfDiagonal + 2 * spacing) continue;
        for (int k = bk * E; k < std::min(bk * E + E, grid.Dimensions[2]); ++k)
          for (int j = bj * E; j < std::min(bj * E + E, grid.Dimensions[1]); ++j)
            for (int i = bi * E; i < std::min(bi * E + E, grid.Dimensions[0]); ++i) {
              const Vec3 p = grid.Center(i, j, k);
              const double rho = DrillVolume::RampDensity(bone.SignedDistance(p), spacing);
              const bool isProtected = mayProtect && bone.Protected(p);
              if (rho <= 0 && !isProtected) continue;
              const uint8_t q = DrillVolume::Quantize(rho);
              const uint8_t m = q > 0 ? (bone.Material ? bone.Material(p) : uint8_t(1)) : uint8_t(0);
              volume.SetVoxel(i, j, k, q, m, isProtected);
            }
      }
  volume.Finish();
  return true;
}

std::vector<Material> DrillableMaterials(const MaterialTable& table) {
  std::vector<Material> out;
  for (const Material& m : table.Materials())
    if (m.Drillable()) out.push_back(m);
  return out;
}

uint8_t FindDrillMaterial(const std::vector<Material>& materials, const std::string& tissue) {
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
  };
  const std::string key = lower(tissue);
  for (size_t i = 0; i < materials.size(); ++i)
    if (lower(materials[i].Tissue) == key) return static_cast<uint8_t>(i + 1);
  return 0;
}

}  // namespace rp
