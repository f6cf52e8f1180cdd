#pragma once
// Analytic haptic scenes for the tests: planes, grooves, corners, sheets, spheres.
#include <memory>
#include <vector>

#include "rpHapticRenderer.h"

namespace rptest {

/// A quad (two triangles) with corners a, b, c, d in order; flipped if needed so its face
/// normal points along `outward`.
inline rp::TriangleMesh Quad(const rp::Vec3& a, const rp::Vec3& b, const rp::Vec3& c, const rp::Vec3& d,
                             const rp::Vec3& outward) {
  rp::TriangleMesh m;
  m.Points = {a, b, c, d};
  m.Triangles = {{0, 1, 2}, {0, 2, 3}};
  if (rp::Dot(rp::Cross(b - a, c - a), outward) < 0) m.Triangles = {{0, 2, 1}, {0, 3, 2}};
  m.ComputeNormals();
  return m;
}

inline rp::MaterialTable Table(double k, double b, double mus = 0, double mud = 0) {
  rp::MaterialTable t;
  t.Add({"test", k, b, mus, mud});
  return t;
}

inline std::unique_ptr<rp::HapticScene> Scene(std::vector<rp::HapticMeshInput> meshes, const rp::MaterialTable& table) {
  std::vector<std::string> warnings;
  std::string error;
  return rp::HapticScene::Build(meshes, table, warnings, error);
}

inline rp::Pose At(const rp::Vec3& p) {
  rp::Pose pose;
  pose.T = p;
  return pose;
}

/// Moves the tool in a straight line in `steps` ticks (one renderer update each).
inline const rp::RenderOutput& MoveTo(rp::HapticRenderer& r, const rp::Vec3& from, const rp::Vec3& to, int steps) {
  for (int i = 1; i < steps; ++i) r.Update(At(from + (to - from) * (static_cast<double>(i) / steps)));
  return r.Update(At(to));
}

}  // namespace rptest
