#include "rpBlockMesher.h"

#include <algorithm>
#include <cmath>

#include <vtkMarchingCubesTriangleCases.h>

namespace rp {

namespace {
constexpr int E = DrillVolume::BlockEdge;
constexpr int F = E + 3;  // field samples per axis: one before the block, the block, two after
constexpr int C = E + 1;  // cell corners per axis
constexpr double Iso = 127.5;
// VTK's marching-cubes corner order and edges (vtkMarchingCubes.cxx).
constexpr int Corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr int Edge[12][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6}, {7, 6}, {4, 7}, {0, 4}, {1, 5}, {3, 7}, {2, 6}};
inline int FieldIndex(int x, int y, int z) { return ((z + 1) * F + (y + 1)) * F + (x + 1); }
}  // namespace

BlockMesher::BlockMesher(DrillVolume& volume)
    : Volume(volume), Cache(volume.AllocatedBlocks()), Field(F * F * F), EdgeVertex(C * C * C * 3) {}

size_t BlockMesher::UpdateDirty() {
  return this->Volume.TakeDirty([this](int32_t slot) { this->Contour(slot); });
}

void BlockMesher::ContourAll() {
  // Whatever is marked dirty now is covered by this pass.
  this->Volume.TakeDirty([](int32_t) {});
  for (size_t s = 0; s < this->Cache.size(); ++s) this->Contour(static_cast<int32_t>(s));
}

size_t BlockMesher::TriangleCount() const {
  size_t n = 0;
  for (const BlockMesh& b : this->Cache) n += b.TriangleCount();
  return n;
}

size_t BlockMesher::PointCount() const {
  size_t n = 0;
  for (const BlockMesh& b : this->Cache) n += b.Points.size() / 3;
  return n;
}

double BlockMesher::EnclosedVolume() const {
  double volume = 0;
  for (const BlockMesh& b : this->Cache)
    for (size_t t = 0; t + 2 < b.Triangles.size(); t += 3) {
      const float* p0 = &b.Points[3 * b.Triangles[t]];
      const float* p1 = &b.Points[3 * b.Triangles[t + 1]];
      const float* p2 = &b.Points[3 * b.Triangles[t + 2]];
      const Vec3 a{p0[0], p0[1], p0[2]}, c1{p1[0], p1[1], p1[2]}, c2{p2[0], p2[1], p2[2]};
      volume += Dot(a, Cross(c1, c2)) / 6.0;
    }
  return volume;
}

void BlockMesher::Contour(int32_t slot) {
  BlockMesh& mesh = this->Cache[size_t(slot)];
  mesh.Points.clear();
  mesh.Normals.clear();
  mesh.Materials.clear();
  mesh.Triangles.clear();
  const auto& block = this->Volume.BlockCoordinate(slot);
  const int base[3] = {block[0] * E, block[1] * E, block[2] * E};
  const auto& dims = this->Volume.Grid().Dimensions;
  // The block and one voxel before / two after it, read from the 3×3×3 blocks around (their
  // slots looked up once; voxels of blocks not stored, or beyond the grid, are empty).
  const std::atomic<uint8_t>* neighbours[3][3][3];
  for (int dz = 0; dz < 3; ++dz)
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx) {
        const int32_t n = this->Volume.Slot(block[0] + dx - 1, block[1] + dy - 1, block[2] + dz - 1);
        neighbours[dz][dy][dx] = n < 0 ? nullptr : this->Volume.BlockDensities(n);
      }
  bool anyBone = false, anySpace = false;  // over the cells' corners: a surface needs both
  for (int z = -1; z <= E + 1; ++z) {
    const int bz = z < 0 ? 0 : (z < E ? 1 : 2), lz = (z + E) & (E - 1);
    for (int y = -1; y <= E + 1; ++y) {
      const int by = y < 0 ? 0 : (y < E ? 1 : 2), ly = (y + E) & (E - 1);
      for (int x = -1; x <= E + 1; ++x) {
        const int bx = x < 0 ? 0 : (x < E ? 1 : 2), lx = (x + E) & (E - 1);
        const std::atomic<uint8_t>* d = neighbours[bz][by][bx];
        const uint8_t q = d ? d[lx | (ly << DrillVolume::BlockShift) | (lz << (2 * DrillVolume::BlockShift))].load(std::memory_order_relaxed) : 0;
        this->Field[size_t(FieldIndex(x, y, z))] = q;
        if (x >= 0 && y >= 0 && z >= 0 && x <= E && y <= E && z <= E) {
          anyBone = anyBone || q > 127;
          anySpace = anySpace || q <= 127;
        }
      }
    }
  }
  if (!anyBone || !anySpace) return;
  std::fill(this->EdgeVertex.begin(), this->EdgeVertex.end(), -1);
  const DrillGrid& grid = this->Volume.Grid();
  const double h = grid.Spacing;
  const vtkMarchingCubesTriangleCases* cases = vtkMarchingCubesTriangleCases::GetCases();
  auto value = [this](int x, int y, int z) { return this->Field[size_t(FieldIndex(x, y, z))]; };
  auto gradient = [&](int x, int y, int z) {
    return Vec3{value(x + 1, y, z) - value(x - 1, y, z), value(x, y + 1, z) - value(x, y - 1, z),
                value(x, y, z + 1) - value(x, y, z - 1)};
  };
  // The vertex on the edge from corner a (lower) along `axis`, created once per block.
  auto vertex = [&](const int a[3], const int b[3], int axis) -> uint32_t {
    int32_t& id = this->EdgeVertex[size_t(((a[2] * C + a[1]) * C + a[0]) * 3 + axis)];
    if (id >= 0) return uint32_t(id);
    const double sa = value(a[0], a[1], a[2]), sb = value(b[0], b[1], b[2]);
    const double t = sa == sb ? 0.5 : (Iso - sa) / (sb - sa);
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = base[k] + a[k] + t * (b[k] - a[k]);
    const Vec3 n = -(gradient(a[0], a[1], a[2]) * (1 - t) + gradient(b[0], b[1], b[2]) * t);
    const Vec3 unit = Normalized(n);
    id = static_cast<int32_t>(mesh.Points.size() / 3);
    mesh.Points.insert(mesh.Points.end(), {float(grid.Origin.x + p[0] * h), float(grid.Origin.y + p[1] * h),
                                           float(grid.Origin.z + p[2] * h)});
    mesh.Normals.insert(mesh.Normals.end(), {float(unit.x), float(unit.y), float(unit.z)});
    const int* bone = sa >= sb ? a : b;  // the bone end of the edge
    mesh.Materials.push_back(this->Volume.MaterialCode(base[0] + bone[0], base[1] + bone[1], base[2] + bone[2]) &
                             DrillVolume::MaterialMask);
    return uint32_t(id);
  };
  for (int z = 0; z < E; ++z) {
    if (base[2] + z + 1 >= dims[2]) break;
    for (int y = 0; y < E; ++y) {
      if (base[1] + y + 1 >= dims[1]) break;
      for (int x = 0; x < E; ++x) {
        if (base[0] + x + 1 >= dims[0]) break;
        int index = 0;
        for (int c = 0; c < 8; ++c)
          if (value(x + Corner[c][0], y + Corner[c][1], z + Corner[c][2]) >= Iso) index |= 1 << c;
        if (index == 0 || index == 255) continue;
        const int* edges = cases[index].edges;
        for (; edges[0] > -1; edges += 3) {
          uint32_t ids[3];
          for (int v = 0; v < 3; ++v) {
            const int* e = Edge[edges[v]];
            // The edge's corners relative to the block.
            const int a[3] = {x + Corner[e[0]][0], y + Corner[e[0]][1], z + Corner[e[0]][2]};
            const int b[3] = {x + Corner[e[1]][0], y + Corner[e[1]][1], z + Corner[e[1]][2]};
            int axis = 0;
            while (axis < 2 && a[axis] == b[axis]) ++axis;
            const bool ordered = a[axis] < b[axis];
            ids[v] = ordered ? vertex(a, b, axis) : vertex(b, a, axis);
          }
          if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) continue;
          mesh.Triangles.insert(mesh.Triangles.end(), {ids[0], ids[1], ids[2]});
        }
      }
    }
  }
}

TriangleMesh ContourToTriangleMesh(DrillVolume& volume) {
  TriangleMesh mesh;
  BlockMesher mesher(volume);
  mesher.ContourAll();
  for (const BlockMesh& b : mesher.Blocks()) {
    const int32_t base = static_cast<int32_t>(mesh.Points.size());
    for (size_t p = 0; p < b.Points.size(); p += 3) mesh.Points.push_back({b.Points[p], b.Points[p + 1], b.Points[p + 2]});
    for (size_t t = 0; t < b.Triangles.size(); t += 3)
      mesh.Triangles.push_back({base + int32_t(b.Triangles[t]), base + int32_t(b.Triangles[t + 1]), base + int32_t(b.Triangles[t + 2])});
  }
  return mesh;
}

}  // namespace rp
