#pragma once
// A uniform grid of a triangle mesh's triangles, for exact closest-point queries against a large
// surface that is built once and queried a few thousand times (a level of detail's deviation from
// the full-resolution surface): built in two linear passes over the triangles, with no sort and no
// tree, several times quicker to build than the BVH on a display surface of 10^5-10^6 triangles.
// The BVH (rpBVH.h) stays the structure of the servo loop and the drill, where a surface is built
// rarely and queried millions of times.
#include <cstdint>
#include <vector>

#include "rpBVH.h"
#include "rpTriangleMesh.h"

namespace rp {

class TriangleGrid {
 public:
  /// Bins the triangles of `mesh` into the cells their bounding boxes overlap (zero-area triangles
  /// skipped, as in the BVH). Keeps a pointer to `mesh`, which must outlive the grid unchanged.
  void Build(const TriangleMesh& mesh);
  bool Empty() const { return this->Entries.empty(); }
  double CellSize() const { return this->Cell; }

  /// Closest surface point within `maxDistance` (infinity for no limit); false when none. Const,
  /// thread-safe, noexcept, never allocates: the same answer as BVH::ClosestPoint.
  bool ClosestPoint(const Vec3& query, double maxDistance, ClosestPointHit& hit) const noexcept;
  /// Whether some triangle is within `distance` of `query`: stops at the first one found (the
  /// query of a Hausdorff distance, where a point closer than the largest distance so far cannot
  /// change it). Same guarantees as ClosestPoint.
  bool AnyWithin(const Vec3& query, double distance) const noexcept;

 private:
  // Visits the triangles of the cells that can hold one within sqrt(limit2) of `query`, nearest
  // cells first; `visit(triangle, closestPoint, bary, distance2)` lowers `limit2` as it finds
  // closer ones and returns true to stop.
  template <class Visit>
  void Search(const Vec3& query, double& limit2, const Visit& visit) const noexcept;

  const TriangleMesh* Mesh = nullptr;
  Vec3 Origin;
  double Cell = 1.0;
  int Dims[3] = {0, 0, 0};
  std::vector<uint32_t> CellStart;  // per cell, the first of its entries; one more at the end
  std::vector<uint32_t> Entries;    // triangle indices, cell by cell
};

}  // namespace rp
