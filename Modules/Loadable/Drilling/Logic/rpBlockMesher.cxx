#include "rpBlockMesher.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <vtkMarchingCubesTriangleCases.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

namespace rp {

namespace {
constexpr int E = DrillVolume::BlockEdge;
constexpr int F = E + 3;  // field samples per axis: one before the block, the block, two after
constexpr int C = E + 1;  // cell corners per axis
constexpr double Iso = 127.5;
constexpr uint8_t Bone = 128;  // a sample >= Bone is inside (above Iso)
constexpr uint16_t FullRow = (1u << C) - 1;
// VTK's marching-cubes corner order and edges (vtkMarchingCubes.cxx).
constexpr int Corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr int Edge[12][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6}, {7, 6}, {4, 7}, {0, 4}, {1, 5}, {3, 7}, {2, 6}};
inline int FieldIndex(int x, int y, int z) { return ((z + 1) * F + (y + 1)) * F + (x + 1); }
void Clear(BlockMesh& mesh) {  // keeps the capacity: the block is re-contoured in place
  mesh.Points.clear(), mesh.Normals.clear(), mesh.Materials.clear(), mesh.Triangles.clear();
}

// A row of a block is 8 densities in a row in memory: read as one 8-byte atomic load (relaxed,
// as the byte loads elsewhere; the servo thread's byte stores are atomic too). Aligned: the
// densities are one new[] (16-byte aligned) of 512-byte blocks. Bytes in memory order (x86-64).
static_assert(E == 8, "a block row is one 64-bit word");
constexpr uint64_t HighBits = 0x8080808080808080ull;  // a density >= Bone (128) has its high bit set
inline uint64_t LoadRow(const std::atomic<uint8_t>* row) {
  return __atomic_load_n(reinterpret_cast<const uint64_t*>(row), __ATOMIC_RELAXED);
}
// The high bit of each byte of a row (x = 0..7), packed into bits 0..7.
inline unsigned InsideBits(uint64_t row) { return unsigned(((row & HighBits) * 0x0002040810204081ull) >> 56); }

// Each edge as its lower corner and the axis it runs along (a vertex is cached by both).
struct EdgeStart {
  int Lower[3];
  int Axis;
};
constexpr EdgeStart MakeEdgeStart(int e) {
  const int* a = Corner[Edge[e][0]];
  const int* b = Corner[Edge[e][1]];
  int axis = 0;
  while (axis < 2 && a[axis] == b[axis]) ++axis;
  const int* lower = a[axis] < b[axis] ? a : b;
  return {{lower[0], lower[1], lower[2]}, axis};
}
constexpr EdgeStart EdgeStarts[12] = {MakeEdgeStart(0), MakeEdgeStart(1), MakeEdgeStart(2),  MakeEdgeStart(3),
                                      MakeEdgeStart(4), MakeEdgeStart(5), MakeEdgeStart(6),  MakeEdgeStart(7),
                                      MakeEdgeStart(8), MakeEdgeStart(9), MakeEdgeStart(10), MakeEdgeStart(11)};
}  // namespace

// One block's samples, the inside bits of its cell corners, its edge vertices and its output
// before it is copied to the block's cache entry (one allocation per array there).
struct BlockMesher::Scratch {
  static constexpr int MaxVertices = C * C * C * 3;  // one per (corner, axis)
  static constexpr int MaxTriangles = E * E * E * 5;  // at most 5 per cell
  uint8_t Field[F * F * F];
  uint16_t Rows[C][C];                 // bit x of Rows[z][y]: corner (x, y, z) is inside
  int32_t EdgeVertex[MaxVertices];     // vertex of each (corner, axis), −1 none
  float Points[3 * MaxVertices], Normals[3 * MaxVertices];
  uint8_t Materials[MaxVertices];
  uint32_t Triangles[3 * MaxTriangles];
};

// Each SMP thread's scratch, kept from one parallel pass to the next (a frame of many dirty
// blocks allocates nothing once each thread has its own).
struct BlockMesher::ThreadScratches {
  vtkSMPThreadLocal<Scratch*> Local{nullptr};
  ~ThreadScratches() {
    for (Scratch* scratch : this->Local) delete scratch;
  }
};

BlockMesher::BlockMesher(DrillVolume& volume)
    : Volume(volume), Cache(volume.AllocatedBlocks()), Own(new Scratch), Scratches(new ThreadScratches) {
  this->Slots.reserve(volume.AllocatedBlocks());
}

BlockMesher::~BlockMesher() = default;

size_t BlockMesher::UpdateDirty() {
  this->Slots.clear();
  this->Volume.TakeDirty([this](int32_t slot) { this->Slots.push_back(slot); });
  if (this->Slots.size() < ParallelBlocks) {
    for (int32_t slot : this->Slots) this->ContourBlock(slot, *this->Own);
  } else {
    this->ContourSlots(this->Slots.data(), this->Slots.size());
  }
  return this->Slots.size();
}

void BlockMesher::ContourAll() {
  // Whatever is marked dirty now is covered by this pass.
  this->Volume.TakeDirty([](int32_t) {});
  this->Slots.resize(this->Cache.size());
  for (size_t s = 0; s < this->Slots.size(); ++s) this->Slots[s] = static_cast<int32_t>(s);
  this->ContourSlots(this->Slots.data(), this->Slots.size());
}

void BlockMesher::Contour(int32_t slot) { this->ContourBlock(slot, *this->Own); }

uint8_t BlockMesher::BlockSide(int32_t slot) const {
  if (slot < 0) return 0;  // a block never stored is empty
  const std::atomic<uint8_t>* d = this->Volume.BlockDensities(slot);
  uint64_t all = HighBits, any = 0;
  for (int row = 0; row < DrillVolume::BlockVoxels; row += E) {
    const uint64_t w = LoadRow(d + row) & HighBits;
    all &= w, any |= w;
  }
  return all == HighBits ? 1 : (any == 0 ? 0 : 2);
}

void BlockMesher::ClassifyBlocks() {
  // Which side of ½ each block's voxels are on: most of a bone's blocks are all bone.
  this->Sides.resize(this->Cache.size());
  vtkSMPTools::For(0, static_cast<vtkIdType>(this->Cache.size()), [this](vtkIdType s0, vtkIdType s1) {
    for (vtkIdType s = s0; s < s1; ++s) this->Sides[size_t(s)] = this->BlockSide(static_cast<int32_t>(s));
  });
}

template <class SideOf>
bool BlockMesher::CrossesNoSurface(int32_t slot, SideOf sideOf) const {
  // The block's cells reach into the blocks after it along x, y and z (missing ones are empty):
  // no surface when all of them are on the block's side.
  const uint8_t side = sideOf(slot);
  if (side == 2) return false;
  const auto& b = this->Volume.BlockCoordinate(slot);
  for (int n = 1; n < 8; ++n) {
    const int32_t next = this->Volume.Slot(b[0] + (n & 1), b[1] + ((n >> 1) & 1), b[2] + (n >> 2));
    if (sideOf(next) != side) return false;
  }
  return true;
}

void BlockMesher::ContourSlots(const int32_t* slots, size_t count) {
  // The sides of every block in one pass when most blocks are asked for (the whole bone, a
  // reset); otherwise (a frame's or an undo's dirty blocks) each block's own and its neighbours'
  // sides as it is met: a pass over the whole volume cost more than contouring them (44 000
  // blocks at 0.2 mm, 1 ms a frame).
  const bool wholePass = count * 8 >= this->Cache.size();
  if (wholePass) this->ClassifyBlocks();
  vtkSMPThreadLocal<Scratch*>& scratches = this->Scratches->Local;
  const auto stored = [this](int32_t s) { return s < 0 ? uint8_t(0) : this->Sides[size_t(s)]; };
  const auto measured = [this](int32_t s) { return this->BlockSide(s); };
  vtkSMPTools::For(0, static_cast<vtkIdType>(count), [&](vtkIdType i0, vtkIdType i1) {
    Scratch*& scratch = scratches.Local();
    if (!scratch) scratch = new Scratch;
    for (vtkIdType i = i0; i < i1; ++i) {
      const int32_t slot = slots[i];
      const bool empty =
          wholePass ? this->CrossesNoSurface(slot, stored) : this->CrossesNoSurface(slot, measured);
      if (empty) {
        Clear(this->Cache[size_t(slot)]);
      } else {
        this->ContourBlock(slot, *scratch);
      }
    }
  });
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

void BlockMesher::ContourBlock(int32_t slot, Scratch& scratch) {
  BlockMesh& mesh = this->Cache[size_t(slot)];
  int vertices = 0, triangles = 0;
  const auto& block = this->Volume.BlockCoordinate(slot);
  const int base[3] = {block[0] * E, block[1] * E, block[2] * E};
  const auto& dims = this->Volume.Grid().Dimensions;
  // The block and one voxel before / two after it, read from the 3×3×3 blocks around (their
  // slots looked up once; voxels of blocks not stored, or beyond the grid, are empty), a row
  // of 11 samples at a time: one from the block before along x, 8 from the block, 2 after.
  const std::atomic<uint8_t>* neighbours[3][3][3];
  for (int dz = 0; dz < 3; ++dz)
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx) {
        const int32_t n = this->Volume.Slot(block[0] + dx - 1, block[1] + dy - 1, block[2] + dz - 1);
        neighbours[dz][dy][dx] = n < 0 ? nullptr : this->Volume.BlockDensities(n);
      }
  uint8_t* field = scratch.Field;
  auto load = [](const std::atomic<uint8_t>* d, int local) -> uint8_t {
    return d ? d[local].load(std::memory_order_relaxed) : uint8_t(0);
  };
  // Inside bits of the cell corners [0, E]³ as they are read, one row of C bits per (y, z): a
  // surface needs both kinds of corner.
  unsigned any = 0, all = FullRow;
  for (int z = -1; z <= E + 1; ++z) {
    const int bz = z < 0 ? 0 : (z < E ? 1 : 2), lz = (z + E) & (E - 1);
    for (int y = -1; y <= E + 1; ++y) {
      const int by = y < 0 ? 0 : (y < E ? 1 : 2), ly = (y + E) & (E - 1);
      const int row = (ly << DrillVolume::BlockShift) | (lz << (2 * DrillVolume::BlockShift));
      const std::atomic<uint8_t>* const* d = neighbours[bz][by];
      uint8_t* f = field + FieldIndex(-1, y, z);
      const uint64_t middle = d[1] ? LoadRow(d[1] + row) : 0;
      f[0] = load(d[0], row | (E - 1));
      std::memcpy(f + 1, &middle, E);
      f[E + 1] = load(d[2], row);
      f[E + 2] = load(d[2], row | 1);
      if (y >= 0 && z >= 0 && y < C && z < C) {
        const unsigned bits = InsideBits(middle) | (unsigned(f[E + 1] >= Bone) << E);
        scratch.Rows[z][y] = uint16_t(bits);
        any |= bits;
        all &= bits;
      }
    }
  }
  if (any == 0 || all == FullRow) {
    Clear(mesh);
    return;
  }
  std::fill(std::begin(scratch.EdgeVertex), std::end(scratch.EdgeVertex), -1);
  const DrillGrid& grid = this->Volume.Grid();
  const double h = grid.Spacing;
  const vtkMarchingCubesTriangleCases* cases = vtkMarchingCubesTriangleCases::GetCases();
  auto value = [field](int x, int y, int z) { return field[FieldIndex(x, y, z)]; };
  auto gradient = [&](int x, int y, int z) {
    return Vec3{double(value(x + 1, y, z) - value(x - 1, y, z)), double(value(x, y + 1, z) - value(x, y - 1, z)),
                double(value(x, y, z + 1) - value(x, y, z - 1))};
  };
  // The vertex on the edge from corner a (lower) along `axis`, created once per block.
  auto vertex = [&](int ax, int ay, int az, int axis) -> uint32_t {
    int32_t& id = scratch.EdgeVertex[((az * C + ay) * C + ax) * 3 + axis];
    if (id >= 0) return uint32_t(id);
    const int a[3] = {ax, ay, az};
    const int b[3] = {ax + (axis == 0), ay + (axis == 1), az + (axis == 2)};
    const double sa = value(a[0], a[1], a[2]), sb = value(b[0], b[1], b[2]);
    const double t = sa == sb ? 0.5 : (Iso - sa) / (sb - sa);
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = base[k] + a[k] + t * (b[k] - a[k]);
    const Vec3 n = -(gradient(a[0], a[1], a[2]) * (1 - t) + gradient(b[0], b[1], b[2]) * t);
    const Vec3 unit = Normalized(n);
    id = vertices++;
    float* point = scratch.Points + 3 * id;
    point[0] = float(grid.Origin.x + p[0] * h), point[1] = float(grid.Origin.y + p[1] * h);
    point[2] = float(grid.Origin.z + p[2] * h);
    float* normal = scratch.Normals + 3 * id;
    normal[0] = float(unit.x), normal[1] = float(unit.y), normal[2] = float(unit.z);
    const int* bone = sa >= sb ? a : b;  // the bone end of the edge
    scratch.Materials[id] = this->Volume.MaterialCode(base[0] + bone[0], base[1] + bone[1], base[2] + bone[2]) &
                            DrillVolume::MaterialMask;
    return uint32_t(id);
  };
  // Cells whose far corner is beyond the grid are not contoured.
  const int end[3] = {std::min(E, dims[0] - 1 - base[0]), std::min(E, dims[1] - 1 - base[1]),
                      std::min(E, dims[2] - 1 - base[2])};
  for (int z = 0; z < end[2]; ++z) {
    for (int y = 0; y < end[1]; ++y) {
      // The four corner rows of this row of cells; all inside or all outside: no surface.
      const unsigned r0 = scratch.Rows[z][y], r1 = scratch.Rows[z][y + 1], r2 = scratch.Rows[z + 1][y],
                     r3 = scratch.Rows[z + 1][y + 1];
      if ((r0 | r1 | r2 | r3) == 0 || (r0 & r1 & r2 & r3) == FullRow) continue;
      for (int x = 0; x < end[0]; ++x) {
        // Corner order as Corner[]: (x, y, z), (x+1, y, z), (x+1, y+1, z), (x, y+1, z), then z + 1.
        const int index = ((r0 >> x) & 1) | (((r0 >> (x + 1)) & 1) << 1) | (((r1 >> (x + 1)) & 1) << 2) |
                          (((r1 >> x) & 1) << 3) | (((r2 >> x) & 1) << 4) | (((r2 >> (x + 1)) & 1) << 5) |
                          (((r3 >> (x + 1)) & 1) << 6) | (((r3 >> x) & 1) << 7);
        if (index == 0 || index == 255) continue;
        for (const int* edges = cases[index].edges; edges[0] > -1; edges += 3) {
          uint32_t ids[3];
          for (int v = 0; v < 3; ++v) {
            const EdgeStart& e = EdgeStarts[edges[v]];
            ids[v] = vertex(x + e.Lower[0], y + e.Lower[1], z + e.Lower[2], e.Axis);
          }
          if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) continue;
          uint32_t* triangle = scratch.Triangles + 3 * triangles++;
          triangle[0] = ids[0], triangle[1] = ids[1], triangle[2] = ids[2];
        }
      }
    }
  }
  // One allocation per array of the block's entry (none when it had the room).
  mesh.Points.assign(scratch.Points, scratch.Points + 3 * vertices);
  mesh.Normals.assign(scratch.Normals, scratch.Normals + 3 * vertices);
  mesh.Materials.assign(scratch.Materials, scratch.Materials + vertices);
  mesh.Triangles.assign(scratch.Triangles, scratch.Triangles + 3 * triangles);
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
