#pragma once
// Bounding-volume hierarchy (axis-aligned boxes) over a triangle mesh, for the haptic servo loop:
// closest point and first hit along a segment. Built by sorting triangles along a Morton
// (Z-order) curve of their centroids and splitting each range where its highest differing code
// bit flips (Karras 2012): spatially coherent nodes in O(n log n) with sequential memory access. Built once (allocates); queries are const,
// thread-safe, noexcept and never allocate (fixed-size traversal stack).
#include <cstdint>
#include <vector>

#include "rpTriangleMesh.h"

namespace rp {

struct ClosestPointHit {
  Vec3 Point;              // closest point on the surface
  double Distance2 = 0;    // squared distance to the query
  uint32_t Triangle = 0;   // index in the source mesh
  double Barycentric[3] = {0, 0, 0};
};

struct SegmentHit {
  Vec3 Point;
  double T = 0;            // fraction along the segment, in [0,1]
  uint32_t Triangle = 0;   // index in the source mesh
  double Barycentric[3] = {0, 0, 0};
};

struct SegmentClosestHit {
  Vec3 SegmentPoint;       // on the segment
  Vec3 SurfacePoint;       // on the surface
  double Distance2 = 0;    // squared distance between them (0: the segment crosses the surface)
  double T = 0;            // fraction along the segment of SegmentPoint, in [0,1]
  uint32_t Triangle = 0;   // index in the source mesh
  uint32_t Leaf = 0;       // the tree's own index of that triangle: a warm start for the next query
};

class BVH {
 public:
  /// Builds over `mesh` (keeps its own copy of the triangle corners; `mesh` may go away), on the
  /// machine's threads for a large mesh (the same tree as on one).
  /// Degenerate (zero-area) triangles are skipped.
  void Build(const TriangleMesh& mesh, int maxTrianglesPerLeaf = 4);
  bool Empty() const { return this->Nodes.empty(); }
  size_t NumberOfTriangles() const { return this->Tris.size(); }
  size_t NumberOfNodes() const { return this->Nodes.size(); }

  /// Closest surface point within `maxDistance` (infinity for no limit). False when none.
  bool ClosestPoint(const Vec3& query, double maxDistance, ClosestPointHit& hit) const noexcept;

  enum class Faces { Both, FrontOnly };
  /// First triangle crossed by the segment a→b (smallest T). With FrontOnly, triangles whose
  /// normal points along the segment (exits of a closed surface) are ignored.
  bool FirstHit(const Vec3& a, const Vec3& b, Faces faces, SegmentHit& hit) const noexcept;

  /// Closest pair between the segment a→b and the surface, within `maxDistance` (infinity for no
  /// limit). False when none is that close. `warmLeaf` (a previous hit's Leaf, e.g. of a
  /// neighbouring segment) seeds the search bound: the answer is the same, found sooner. The
  /// distance is 0 where the segment crosses a triangle (then T is the first crossing found, not
  /// necessarily the first along the segment).
  bool ClosestToSegment(const Vec3& a, const Vec3& b, double maxDistance, SegmentClosestHit& hit,
                        const uint32_t* warmLeaf = nullptr) const noexcept;
  /// Squared distance between segment p0→p1 and triangle (a,b,c), with the closest points.
  static double SegmentTriangleDistance2(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c,
                                         Vec3& onSegment, Vec3& onTriangle, double& t) noexcept;

  /// Closest point on triangle (a,b,c) to p, with barycentric weights (Ericson, RTCD 5.1.5).
  static Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                     double bary[3]) noexcept;

  static constexpr int MaxDepth = 64;

 private:
  struct Node {
    Vec3 Lo, Hi;
    uint32_t First = 0;  // leaf: first triangle; inner: index of the right child (left = this+1)
    uint32_t Count = 0;  // leaf: number of triangles; inner: 0
  };
  struct Tri {
    Vec3 A, B, C;
    Vec3 Normal;  // unnormalized (B-A)x(C-A)
    uint32_t Source;
  };
  static uint32_t SplitOf(const std::vector<uint64_t>& codes, uint32_t begin, uint32_t end, int depth);
  static uint32_t BuildRange(std::vector<Node>& nodes, const std::vector<Tri>& tris, const std::vector<uint64_t>& codes,
                             uint32_t begin, uint32_t end, int depth, int leafSize);
  static uint32_t BuildSubtree(std::vector<Node>& nodes, const std::vector<Tri>& tris, const std::vector<uint64_t>& codes,
                               uint32_t begin, uint32_t end, int depth, int leafSize, int threads);

  std::vector<Node> Nodes;
  std::vector<Tri> Tris;  // in leaf order
  // Per triangle (leaf order), for the segment query only (kept apart so the point query's data
  // stays as compact): the centroid and the distance from it to the farthest corner.
  struct Ball {
    Vec3 Center;
    double Radius = 0;
  };
  std::vector<Ball> Balls;
};

}  // namespace rp
