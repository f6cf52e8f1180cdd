#include "rpTriangleMesh.h"

#include <cmath>
#include <unordered_map>

namespace rp {

void TriangleMesh::ComputeNormals() {
  this->FaceNormals.assign(this->Triangles.size(), Vec3{});
  this->VertexNormals.assign(this->Points.size(), Vec3{});
  for (size_t i = 0; i < this->Triangles.size(); ++i) {
    const auto& t = this->Triangles[i];
    const Vec3 p[3] = {this->Points[t[0]], this->Points[t[1]], this->Points[t[2]]};
    const Vec3 n = Normalized(Cross(p[1] - p[0], p[2] - p[0]));
    this->FaceNormals[i] = n;
    for (int k = 0; k < 3; ++k) {
      // Angle weighting keeps the vertex normal independent of how a surface is split into triangles.
      const Vec3 e1 = Normalized(p[(k + 1) % 3] - p[k]);
      const Vec3 e2 = Normalized(p[(k + 2) % 3] - p[k]);
      const double angle = std::acos(std::fmax(-1.0, std::fmin(1.0, Dot(e1, e2))));
      this->VertexNormals[t[k]] += n * angle;
    }
  }
  for (auto& n : this->VertexNormals) n = Normalized(n);
}

void TriangleMesh::Append(const TriangleMesh& other, uint16_t label) {
  if (this->Labels.size() != this->Triangles.size()) this->Labels.resize(this->Triangles.size(), 0);
  const int32_t offset = static_cast<int32_t>(this->Points.size());
  this->Points.insert(this->Points.end(), other.Points.begin(), other.Points.end());
  for (const auto& t : other.Triangles) this->Triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  this->Labels.resize(this->Triangles.size(), label);
  this->FaceNormals.clear();
  this->VertexNormals.clear();
}

bool TriangleMesh::Validate(std::string& error) const {
  if (!this->Labels.empty() && this->Labels.size() != this->Triangles.size()) {
    error = "triangle mesh: " + std::to_string(this->Labels.size()) + " labels for " +
            std::to_string(this->Triangles.size()) + " triangles";
    return false;
  }
  for (size_t i = 0; i < this->Points.size(); ++i) {
    const Vec3& p = this->Points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      error = "triangle mesh: point " + std::to_string(i) + " is not finite";
      return false;
    }
  }
  const int32_t n = static_cast<int32_t>(this->Points.size());
  for (size_t i = 0; i < this->Triangles.size(); ++i) {
    for (int32_t v : this->Triangles[i]) {
      if (v < 0 || v >= n) {
        error = "triangle mesh: triangle " + std::to_string(i) + " refers to point " + std::to_string(v) +
                " of " + std::to_string(n);
        return false;
      }
    }
  }
  return true;
}

namespace shapes {

TriangleMesh Sphere(const Vec3& center, double radius, int subdivisions) {
  TriangleMesh m;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  const Vec3 base[12] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (const Vec3& p : base) m.Points.push_back(Normalized(p));
  m.Triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<uint64_t, int32_t> midpoints;
    midpoints.reserve(m.Triangles.size() * 2);
    auto midpoint = [&](int32_t a, int32_t b) {
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      const int32_t index = static_cast<int32_t>(m.Points.size());
      m.Points.push_back(Normalized(m.Points[a] + m.Points[b]));
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<int32_t, 3>> next;
    next.reserve(m.Triangles.size() * 4);
    for (const auto& t : m.Triangles) {
      const int32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.Triangles.swap(next);
  }
  for (auto& p : m.Points) p = center + p * radius;
  m.ComputeNormals();
  return m;
}

TriangleMesh Box(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.Points.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  // Each face as two CCW triangles seen from outside.
  m.Triangles = {{0, 2, 3}, {0, 3, 1},   // z = lo (normal -z)
                 {4, 5, 7}, {4, 7, 6},   // z = hi (+z)
                 {0, 1, 5}, {0, 5, 4},   // y = lo (-y)
                 {2, 6, 7}, {2, 7, 3},   // y = hi (+y)
                 {0, 4, 6}, {0, 6, 2},   // x = lo (-x)
                 {1, 3, 7}, {1, 7, 5}};  // x = hi (+x)
  m.ComputeNormals();
  return m;
}

TriangleMesh Square(double h, double height) {
  TriangleMesh m;
  m.Points = {{-h, -h, height}, {h, -h, height}, {h, h, height}, {-h, h, height}};
  m.Triangles = {{0, 1, 2}, {0, 2, 3}};
  m.ComputeNormals();
  return m;
}

}  // namespace shapes
}  // namespace rp
