#include "rpMeshSignedDistance.h"

#include <cmath>
#include <unordered_map>

namespace rp {

bool MeshSignedDistance::Build(const TriangleMesh& mesh, std::string& error) {
  this->Surface = mesh;
  this->Tree = BVH{};
  if (!mesh.Validate(error)) return false;
  if (mesh.Triangles.empty()) {
    error = "signed distance: the mesh has no triangles";
    return false;
  }
  this->Surface.ComputeNormals();
  // Each undirected edge must join exactly two triangles that traverse it in opposite directions.
  std::unordered_map<uint64_t, uint32_t> directed;  // (from, to) → triangle
  directed.reserve(mesh.Triangles.size() * 3);
  auto key = [](int32_t a, int32_t b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
  for (size_t t = 0; t < mesh.Triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.Triangles[t][k], b = mesh.Triangles[t][(k + 1) % 3];
      if (!directed.emplace(key(a, b), static_cast<uint32_t>(t)).second) {
        error = "signed distance: edge " + std::to_string(a) + "-" + std::to_string(b) +
                " is used twice in the same direction (non-manifold or inconsistently oriented mesh)";
        return false;
      }
    }
  }
  this->EdgeNormals.assign(mesh.Triangles.size() * 3, Vec3{});
  size_t open = 0;
  for (size_t t = 0; t < mesh.Triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int32_t a = mesh.Triangles[t][k], b = mesh.Triangles[t][(k + 1) % 3];
      const auto other = directed.find(key(b, a));
      if (other == directed.end()) {
        ++open;
        continue;
      }
      this->EdgeNormals[3 * t + k] = this->Surface.FaceNormals[t] + this->Surface.FaceNormals[other->second];
    }
  }
  if (open > 0) {
    error = "signed distance: the mesh is not closed (" + std::to_string(open) + " boundary edges)";
    return false;
  }
  this->Tree.Build(this->Surface);
  this->BoxLo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  this->BoxHi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Vec3& p : mesh.Points) this->BoxLo = Min(this->BoxLo, p), this->BoxHi = Max(this->BoxHi, p);
  return true;
}

bool MeshSignedDistance::SignedDistance(const Vec3& p, double maxDistance, double& distance) const noexcept {
  Vec3 closest;
  return this->SignedDistance(p, maxDistance, distance, closest);
}

bool MeshSignedDistance::SignedDistance(const Vec3& p, double maxDistance, double& distance, Vec3& closest) const noexcept {
  ClosestPointHit hit;
  if (!this->Tree.ClosestPoint(p, maxDistance, hit)) return false;
  const auto& corners = this->Surface.Triangles[hit.Triangle];
  const double* w = hit.Barycentric;
  // The closest feature: a corner (one weight is 1), an edge (one weight is 0) or the face. The
  // closest-point routine returns exact 0 and 1 in those regions.
  Vec3 normal;
  if (w[0] == 1.0) normal = this->Surface.VertexNormals[corners[0]];
  else if (w[1] == 1.0) normal = this->Surface.VertexNormals[corners[1]];
  else if (w[2] == 1.0) normal = this->Surface.VertexNormals[corners[2]];
  else if (w[2] == 0.0) normal = this->EdgeNormals[3 * hit.Triangle + 0];  // corners 0-1
  else if (w[0] == 0.0) normal = this->EdgeNormals[3 * hit.Triangle + 1];  // corners 1-2
  else if (w[1] == 0.0) normal = this->EdgeNormals[3 * hit.Triangle + 2];  // corners 2-0
  else normal = this->Surface.FaceNormals[hit.Triangle];
  const double d = std::sqrt(hit.Distance2);
  distance = Dot(p - hit.Point, normal) < 0 ? -d : d;
  closest = hit.Point;
  return true;
}

double MeshSignedDistance::SignedDistance(const Vec3& p) const noexcept {
  double d = HUGE_VAL;
  this->SignedDistance(p, HUGE_VAL, d);
  return d;
}

}  // namespace rp
