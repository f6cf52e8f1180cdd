#pragma once
// Signed distance to a closed triangle mesh (negative inside): the distance from the BVH's
// closest point, the sign from the angle-weighted pseudonormal of the closest feature (face, edge
// or vertex; Baerentzen & Aanaes, IEEE TVCG 11(3), 2005), which is exact for closed manifold
// meshes. Queries are const, thread-safe and do not allocate.
#include <string>
#include <vector>

#include "rpBVH.h"
#include "rpTriangleMesh.h"

namespace rp {

class MeshSignedDistance {
 public:
  /// Builds over a closed, manifold mesh (every edge shared by exactly two triangles, oriented
  /// consistently). Several closed pieces are fine. False with `error` otherwise.
  bool Build(const TriangleMesh& mesh, std::string& error);
  bool Empty() const { return this->Tree.Empty(); }

  /// Signed distance when the surface is within `maxDistance` of `p`; false (and `distance`
  /// untouched) when it is farther: then only a flood fill or an unbounded query knows the sign.
  bool SignedDistance(const Vec3& p, double maxDistance, double& distance) const noexcept;
  /// The same, with the closest surface point.
  bool SignedDistance(const Vec3& p, double maxDistance, double& distance, Vec3& closest) const noexcept;
  /// Unbounded signed distance.
  double SignedDistance(const Vec3& p) const noexcept;
  /// Bounding box of the surface.
  const Vec3& Lo() const { return this->BoxLo; }
  const Vec3& Hi() const { return this->BoxHi; }
  const TriangleMesh& Mesh() const { return this->Surface; }

 private:
  TriangleMesh Surface;            // with face and angle-weighted vertex normals
  std::vector<Vec3> EdgeNormals;   // 3 per triangle: edge k joins corners k and k+1
  BVH Tree;
  Vec3 BoxLo, BoxHi;
};

}  // namespace rp
