#include "rpTriangleGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rp {

namespace {
// Cells about two mean edges wide: a triangle overlaps a few cells, a query near the surface scans
// its own cell and the few neighbours closer than the best distance so far.
constexpr double CellEdges = 2.0;
// At most this many cells per triangle (a mesh of a few huge triangles, or very uneven ones).
constexpr double MaxCellsPerTriangle = 4.0;
// A triangle's cells, kept from the counting pass for the filling pass: its first cell and its
// extent along each axis in 2 bits (0-3 more cells); larger ones are measured again.
constexpr uint8_t SpanSkipped = 0x40;  // zero area
constexpr uint8_t SpanLarge = 0x80;

bool HasArea(const Vec3& a, const Vec3& b, const Vec3& c) { return Norm2(Cross(b - a, c - a)) != 0; }
}  // namespace

void TriangleGrid::Build(const TriangleMesh& mesh) {
  this->Mesh = &mesh;
  this->CellStart.clear();
  this->Entries.clear();
  const auto& points = mesh.Points;
  const size_t count = mesh.Triangles.size();
  if (points.empty() || count == 0) return;
  auto corner = [&](int32_t index) -> const Vec3& { return points[static_cast<size_t>(index)]; };
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = Min(lo, p);
    hi = Max(hi, p);
  }
  // The cell size from the mean edge of a sample of the triangles (spread over the whole mesh).
  const size_t stride = std::max<size_t>(1, count / 4096);
  double edgeSum = 0;
  size_t sampled = 0;
  for (size_t i = 0; i < count; i += stride) {
    const auto& t = mesh.Triangles[i];
    const Vec3 &a = corner(t[0]), &b = corner(t[1]), &c = corner(t[2]);
    edgeSum += Norm(b - a) + Norm(c - b) + Norm(a - c);
    ++sampled;
  }
  const Vec3 extent = hi - lo;
  const double largest = std::max({extent.x, extent.y, extent.z});
  double cell = std::max({CellEdges * edgeSum / (3.0 * static_cast<double>(sampled)), largest * 1e-6, 1e-12});
  auto cellsAt = [&](double size) {
    return (std::floor(extent.x / size) + 1) * (std::floor(extent.y / size) + 1) * (std::floor(extent.z / size) + 1);
  };
  const double maxCells = MaxCellsPerTriangle * static_cast<double>(count) + 1;
  while (cellsAt(cell) > maxCells) cell *= 1.25;
  this->Cell = cell;
  this->Origin = lo;
  const int dims[3] = {static_cast<int>(std::floor(extent.x / cell)) + 1, static_cast<int>(std::floor(extent.y / cell)) + 1,
                       static_cast<int>(std::floor(extent.z / cell)) + 1};
  std::copy(dims, dims + 3, this->Dims);
  const size_t rowStride = static_cast<size_t>(dims[0]), sliceStride = rowStride * static_cast<size_t>(dims[1]);
  const size_t cells = sliceStride * static_cast<size_t>(dims[2]);
  const double inverse = 1.0 / cell;

  auto range = [&](const Vec3& a, const Vec3& b, const Vec3& c, int from[3], int to[3]) {
    const Vec3 boxLo = (Min(a, Min(b, c)) - lo) * inverse, boxHi = (Max(a, Max(b, c)) - lo) * inverse;
    const double l[3] = {boxLo.x, boxLo.y, boxLo.z}, h[3] = {boxHi.x, boxHi.y, boxHi.z};
    for (int axis = 0; axis < 3; ++axis) {
      from[axis] = std::clamp(static_cast<int>(l[axis]), 0, dims[axis] - 1);
      to[axis] = std::clamp(static_cast<int>(h[axis]), 0, dims[axis] - 1);
    }
  };
  auto forCells = [&](const int from[3], const int to[3], auto&& body) {
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j) {
        const size_t row = static_cast<size_t>(k) * sliceStride + static_cast<size_t>(j) * rowStride;
        for (int i = from[0]; i <= to[0]; ++i) body(row + static_cast<size_t>(i));
      }
  };
  // Two passes: count the entries of each cell (keeping each triangle's cells), then fill them.
  std::vector<uint32_t> firstCell(count);
  std::vector<uint8_t> span(count);
  this->CellStart.assign(cells + 1, 0);
  for (size_t index = 0; index < count; ++index) {
    const auto& t = mesh.Triangles[index];
    const Vec3 &a = corner(t[0]), &b = corner(t[1]), &c = corner(t[2]);
    if (!HasArea(a, b, c)) {
      span[index] = SpanSkipped;
      continue;
    }
    int from[3], to[3];
    range(a, b, c, from, to);
    const int dx = to[0] - from[0], dy = to[1] - from[1], dz = to[2] - from[2];
    firstCell[index] = static_cast<uint32_t>(static_cast<size_t>(from[2]) * sliceStride +
                                             static_cast<size_t>(from[1]) * rowStride + static_cast<size_t>(from[0]));
    span[index] = dx <= 3 && dy <= 3 && dz <= 3 ? static_cast<uint8_t>(dx | dy << 2 | dz << 4) : SpanLarge;
    forCells(from, to, [&](size_t cellIndex) { ++this->CellStart[cellIndex + 1]; });
  }
  for (size_t i = 0; i < cells; ++i) this->CellStart[i + 1] += this->CellStart[i];
  this->Entries.resize(this->CellStart[cells]);
  std::vector<uint32_t> next(this->CellStart.begin(), this->CellStart.end() - 1);
  for (size_t index = 0; index < count; ++index) {
    const uint8_t code = span[index];
    if (code == SpanSkipped) continue;
    int from[3], to[3];
    if (code == SpanLarge) {
      const auto& t = mesh.Triangles[index];
      range(corner(t[0]), corner(t[1]), corner(t[2]), from, to);
    } else {
      size_t first = firstCell[index];
      from[2] = static_cast<int>(first / sliceStride);
      first %= sliceStride;
      from[1] = static_cast<int>(first / rowStride);
      from[0] = static_cast<int>(first % rowStride);
      to[0] = from[0] + (code & 3), to[1] = from[1] + (code >> 2 & 3), to[2] = from[2] + (code >> 4 & 3);
    }
    forCells(from, to, [&](size_t cellIndex) { this->Entries[next[cellIndex]++] = static_cast<uint32_t>(index); });
  }
  if (this->Entries.empty()) this->CellStart.clear();
}

template <class Visit>
void TriangleGrid::Search(const Vec3& query, double& limit2, const Visit& visit) const noexcept {
  const TriangleMesh& mesh = *this->Mesh;
  const Vec3 local = query - this->Origin;
  const double q[3] = {local.x, local.y, local.z};
  // The query's cell (outside the grid for a query outside the mesh's box), and the Chebyshev
  // distance, in cells, from it to the nearest and the farthest cell of the grid.
  long centre[3];
  long first = 0, last = 0;
  for (int a = 0; a < 3; ++a) {
    centre[a] = static_cast<long>(std::floor(q[a] / this->Cell));
    const long dims = this->Dims[a];
    first = std::max(first, centre[a] < 0 ? -centre[a] : centre[a] >= dims ? centre[a] - dims + 1 : 0L);
    last = std::max(last, std::max(std::labs(centre[a]), std::labs(dims - 1 - centre[a])));
  }
  bool stop = false;
  auto scanCell = [&](long i, long j, long k) {
    // Squared distance from the query to the cell's box: a cell no closer than the limit is skipped.
    const long index[3] = {i, j, k};
    double box2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double cellLo = static_cast<double>(index[a]) * this->Cell, cellHi = cellLo + this->Cell;
      const double gap = q[a] < cellLo ? cellLo - q[a] : q[a] > cellHi ? q[a] - cellHi : 0.0;
      box2 += gap * gap;
    }
    if (box2 > limit2) return;
    const size_t cell = (static_cast<size_t>(k) * static_cast<size_t>(this->Dims[1]) + static_cast<size_t>(j)) *
                            static_cast<size_t>(this->Dims[0]) + static_cast<size_t>(i);
    for (uint32_t e = this->CellStart[cell]; e < this->CellStart[cell + 1] && !stop; ++e) {
      const uint32_t triangle = this->Entries[e];
      const auto& t = mesh.Triangles[triangle];
      double bary[3];
      const Vec3 point = BVH::ClosestPointOnTriangle(query, mesh.Points[static_cast<size_t>(t[0])],
                                                     mesh.Points[static_cast<size_t>(t[1])],
                                                     mesh.Points[static_cast<size_t>(t[2])], bary);
      stop = visit(triangle, point, bary, Norm2(point - query));
    }
  };
  // Rings of cells at Chebyshev distance `ring` from the query's cell, nearest first: every cell of
  // ring r is at least (r - 1) cells away, so the search ends once that exceeds the limit.
  for (long ring = first; ring <= last && !stop; ++ring) {
    const double bound = static_cast<double>(ring - 1) * this->Cell;
    if (ring > 1 && bound * bound > limit2) break;
    long from[3], to[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(0L, centre[a] - ring);
      to[a] = std::min(static_cast<long>(this->Dims[a]) - 1, centre[a] + ring);
      inside = inside && from[a] <= to[a];
    }
    if (!inside) continue;
    for (long k = from[2]; k <= to[2] && !stop; ++k)
      for (long j = from[1]; j <= to[1] && !stop; ++j) {
        if (std::labs(k - centre[2]) == ring || std::labs(j - centre[1]) == ring) {
          for (long i = from[0]; i <= to[0] && !stop; ++i) scanCell(i, j, k);
        } else {  // inside the ring's box: only its two ends along x belong to the ring
          for (const long i : {centre[0] - ring, centre[0] + ring})
            if (i >= 0 && i < this->Dims[0] && !stop) scanCell(i, j, k);
        }
      }
  }
}

bool TriangleGrid::ClosestPoint(const Vec3& query, double maxDistance, ClosestPointHit& hit) const noexcept {
  if (this->Entries.empty()) return false;
  double limit2 = std::isfinite(maxDistance) ? maxDistance * maxDistance : std::numeric_limits<double>::infinity();
  bool found = false;
  this->Search(query, limit2, [&](uint32_t triangle, const Vec3& point, const double bary[3], double d2) {
    if (d2 <= limit2 && (!found || d2 < hit.Distance2)) {
      found = true;
      limit2 = d2;
      hit.Point = point;
      hit.Distance2 = d2;
      hit.Triangle = triangle;
      std::copy(bary, bary + 3, hit.Barycentric);
    }
    return false;
  });
  return found;
}

bool TriangleGrid::AnyWithin(const Vec3& query, double distance) const noexcept {
  if (this->Entries.empty() || !(distance >= 0)) return false;
  double limit2 = distance * distance;
  bool found = false;
  this->Search(query, limit2, [&](uint32_t, const Vec3&, const double*, double d2) { return found = d2 <= limit2; });
  return found;
}

}  // namespace rp
