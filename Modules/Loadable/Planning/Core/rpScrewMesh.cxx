#include "rpScrewMesh.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rp {

TriangleMesh MakeScrewMesh(const TrajectorySnapshot& screw, int segments) {
  segments = std::max(3, segments);
  const double r = 0.5 * screw.ScrewDiameterMm, length = screw.ScrewLengthMm;
  const double tip = std::min(r, 0.5 * length), head = 0.5 * screw.HeadDiameterMm;
  // The profile from the tip back: (distance from the target along -u, radius), ending on the axis.
  std::vector<std::pair<double, double>> profile = {{0, 0}, {tip, r}, {length, r}};
  if (screw.HeadLengthMm > 0 && head > 0) {
    profile.push_back({length, head});
    profile.push_back({length + screw.HeadLengthMm, head});
    profile.push_back({length + screw.HeadLengthMm, 0});
  } else {
    profile.push_back({length, 0});
  }
  const Vec3 u = screw.Direction();
  const Vec3 a = std::fabs(u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = Normalized(Cross(u, a)), e2 = Cross(u, e1);
  TriangleMesh mesh;
  // Poles: the first and last profile points; rings in between.
  mesh.Points.push_back(screw.Target);
  const int rings = static_cast<int>(profile.size()) - 2;
  for (int k = 1; k <= rings; ++k) {
    const auto [back, radius] = profile[static_cast<size_t>(k)];
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * 3.14159265358979323846 * s / segments;
      mesh.Points.push_back(screw.Target - u * back + (e1 * std::cos(angle) + e2 * std::sin(angle)) * radius);
    }
  }
  mesh.Points.push_back(screw.Target - u * profile.back().first);
  const int32_t last = static_cast<int32_t>(mesh.Points.size()) - 1;
  auto ring = [&](int k, int s) { return static_cast<int32_t>(1 + (k - 1) * segments + (s % segments)); };
  // Outward: e1 -> e2 turns counter-clockwise about u, and the rings go from the tip backwards.
  for (int s = 0; s < segments; ++s) mesh.Triangles.push_back({0, ring(1, s), ring(1, s + 1)});
  for (int k = 1; k < rings; ++k)
    for (int s = 0; s < segments; ++s) {
      mesh.Triangles.push_back({ring(k, s), ring(k + 1, s + 1), ring(k, s + 1)});
      mesh.Triangles.push_back({ring(k, s), ring(k + 1, s), ring(k + 1, s + 1)});
    }
  for (int s = 0; s < segments; ++s) mesh.Triangles.push_back({last, ring(rings, s + 1), ring(rings, s)});
  mesh.ComputeNormals();
  return mesh;
}

}  // namespace rp
