#pragma once
// Drillable bones with a closed-form shape: a signed distance function (mm, < 0 inside), the
// material inside, optionally protected regions. Used by `roboplan drill --block`, the tests
// (known volumes and forces) and the benchmark.
#include <functional>
#include <string>
#include <vector>

#include "rpDrillVolume.h"

namespace rp {

struct AnalyticBone {
  std::function<double(const Vec3&)> SignedDistance;  // exact (1-Lipschitz) signed distance, mm
  std::function<uint8_t(const Vec3&)> Material;       // 1-based material at a point in the bone (default 1)
  std::function<bool(const Vec3&)> Protected;         // optional: protected points (bone or not)
  Vec3 Lo, Hi;  // RAS bounds of the bone and of the protected regions
};

/// Fills `volume` with the bone on a grid of `spacing` covering its bounds plus a margin.
bool BuildAnalyticBone(const AnalyticBone& bone, double spacing, const std::vector<Material>& materials,
                       DrillVolume& volume, std::string& error);

/// Signed distance to an axis-aligned box (exact inside and outside).
double BoxSignedDistance(const Vec3& p, const Vec3& lo, const Vec3& hi);

/// A homogeneous block, or (shell > 0) a cortical shell of that thickness around a trabecular
/// core. `cortical`/`trabecular` are 1-based materials.
AnalyticBone BlockBone(const Vec3& lo, const Vec3& hi, uint8_t cortical, double shell = 0, uint8_t trabecular = 0);

/// The drillable materials of a material table (those with a hardness), in table order.
std::vector<Material> DrillableMaterials(const MaterialTable& table);
/// 1-based index of `tissue` among `materials` (case-insensitive), 0 when absent.
uint8_t FindDrillMaterial(const std::vector<Material>& materials, const std::string& tissue);

}  // namespace rp
