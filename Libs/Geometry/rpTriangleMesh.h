#pragma once
// An indexed triangle mesh for haptics and distance queries (plain C++, no VTK), with a label
// per triangle (e.g. the material / tissue index when several meshes are merged), face normals
// and vertex normals (for force shading). Analytic shapes for tests and benchmarks.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rpVec3.h"

namespace rp {

struct TriangleMesh {
  std::vector<Vec3> Points;
  std::vector<std::array<int32_t, 3>> Triangles;  // counter-clockwise seen from outside
  std::vector<uint16_t> Labels;                   // one per triangle (empty: all 0)
  std::vector<Vec3> FaceNormals;                  // ComputeNormals()
  std::vector<Vec3> VertexNormals;                // angle-weighted; ComputeNormals()

  size_t NumberOfTriangles() const { return this->Triangles.size(); }
  uint16_t Label(size_t triangle) const { return this->Labels.empty() ? 0 : this->Labels[triangle]; }
  /// Face normals and angle-weighted vertex normals (degenerate faces get a zero normal).
  void ComputeNormals();
  /// Appends another mesh; its triangles get `label`.
  void Append(const TriangleMesh& other, uint16_t label);
  /// Indices in range, no NaN, labels sized right. Returns false and names the problem.
  bool Validate(std::string& error) const;
};

namespace shapes {
/// Icosphere: 20·4^subdivisions triangles, outward normals.
TriangleMesh Sphere(const Vec3& center, double radius, int subdivisions);
/// Axis-aligned box, 12 triangles, outward normals.
TriangleMesh Box(const Vec3& minCorner, const Vec3& maxCorner);
/// A single square (two triangles) in the plane z = height, normal +z, half-size `halfSize`.
TriangleMesh Square(double halfSize, double height);
}  // namespace shapes

}  // namespace rp
