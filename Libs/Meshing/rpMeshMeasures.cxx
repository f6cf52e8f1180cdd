#include "rpMeshMeasures.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

namespace rp {

namespace {

// Sorted edge keys, one per use of an edge by a triangle: a run of one is a boundary edge, a run
// of more than two a non-manifold edge.
template <typename Key>
void CountEdgeUses(const std::vector<Key>& sorted, long& boundary, long& nonManifold) {
  for (size_t i = 0; i < sorted.size();) {
    size_t j = i + 1;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    if (j - i == 1) ++boundary;
    else if (j - i > 2) ++nonManifold;
    i = j;
  }
}

}  // namespace

void CountBadEdges(vtkPolyData* mesh, long& boundaryEdges, long& nonManifoldEdges) {
  boundaryEdges = nonManifoldEdges = 0;
  // Every edge key once per triangle side, sorted: a run of 2 is a manifold edge.
  std::vector<uint64_t> edges;
  edges.reserve(static_cast<size_t>(mesh->GetPolys()->GetNumberOfConnectivityIds()));
  vtkCellArray* polys = mesh->GetPolys();
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    for (vtkIdType e = 0; e < n; ++e) {
      uint64_t a = static_cast<uint64_t>(ids[e]), c = static_cast<uint64_t>(ids[(e + 1) % n]);
      if (a > c) std::swap(a, c);
      edges.push_back((a << 32) | c);
    }
  }
  vtkSMPTools::Sort(edges.begin(), edges.end());
  CountEdgeUses(edges, boundaryEdges, nonManifoldEdges);
}

long CountNonManifoldVertices(vtkPolyData* mesh) { return CountTopology(mesh).NonManifoldVertices; }

MeshTopology CountTopology(vtkPolyData* mesh) {
  // Per vertex, the edges opposite it in its triangles (its link): a closed fan is one cycle, and
  // edge (v, w) lies in as many triangles as v's link has edges ending at w.
  const vtkIdType np = mesh->GetNumberOfPoints();
  vtkCellArray* polys = mesh->GetPolys();
  std::vector<vtkIdType> start(static_cast<size_t>(np) + 1, 0);
  bool triangles = true;  // only triangles with three different corners: else edges the general way
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3 || ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) triangles = false;
    if (n == 3)
      for (int k = 0; k < 3; ++k) ++start[static_cast<size_t>(ids[k]) + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<std::array<vtkIdType, 2>> link(static_cast<size_t>(start.back()));
  std::vector<vtkIdType> fill(start.begin(), start.end() - 1);
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
    if (n == 3)
      for (int k = 0; k < 3; ++k) link[static_cast<size_t>(fill[static_cast<size_t>(ids[k])]++)] = {ids[(k + 1) % 3], ids[(k + 2) % 3]};
  std::atomic<long> badVertices{0}, boundaryEdges{0}, nonManifoldEdges{0};
  vtkSMPTools::For(0, np, [&](vtkIdType v0, vtkIdType v1) {
    std::vector<std::array<vtkIdType, 2>> edges;
    std::vector<vtkIdType> ends;
    long bad = 0, boundary = 0, nonManifold = 0;
    for (vtkIdType v = v0; v < v1; ++v) {
      const size_t b = static_cast<size_t>(start[static_cast<size_t>(v)]), e = static_cast<size_t>(start[static_cast<size_t>(v) + 1]);
      if (b == e) continue;
      edges.assign(link.begin() + static_cast<long>(b), link.begin() + static_cast<long>(e));
      if (triangles) {
        // Each edge (v, w) once, from its smaller end.
        ends.clear();
        for (const auto& edge : edges)
          for (vtkIdType w : edge)
            if (w > v) ends.push_back(w);
        std::sort(ends.begin(), ends.end());
        CountEdgeUses(ends, boundary, nonManifold);
      }
      // Walk the cycle from the first edge: a single fan visits every edge.
      size_t visited = 1;
      vtkIdType first = edges[0][0], at = edges[0][1];
      edges[0] = {-1, -1};
      bool closed = false;
      while (!closed) {
        bool found = false;
        for (auto& edge : edges) {
          if (edge[0] != at) continue;  // oriented fans: next edge starts where this one ends
          at = edge[1];
          edge = {-1, -1};
          ++visited;
          found = true;
          break;
        }
        if (!found || at == first) closed = true;
      }
      if (at != first || visited != edges.size()) ++bad;
    }
    badVertices += bad, boundaryEdges += boundary, nonManifoldEdges += nonManifold;
  });
  MeshTopology topology;
  topology.NonManifoldVertices = badVertices;
  if (triangles) {
    topology.BoundaryEdges = boundaryEdges, topology.NonManifoldEdges = nonManifoldEdges;
  } else {
    CountBadEdges(mesh, topology.BoundaryEdges, topology.NonManifoldEdges);
  }
  return topology;
}

void MeshVolumeAndArea(vtkPolyData* mesh, double& volume, double& area) {
  volume = area = 0;
  vtkPoints* points = mesh->GetPoints();
  vtkCellArray* polys = mesh->GetPolys();
  if (!points || !polys || polys->GetNumberOfCells() == 0) return;
  // Triangle fans of every polygon, summed in parallel (meshes have millions of triangles).
  const PointsView view(points);
  // Ids read in place when the storage is vtkIdType-sized (then thread-safe), else copied.
  const bool shared = polys->IsStorageShareable();
  vtkSMPThreadLocal<std::array<double, 2>> sums(std::array<double, 2>{0.0, 0.0});
  vtkSMPTools::For(0, polys->GetNumberOfCells(), [&](vtkIdType c0, vtkIdType c1) {
    auto& local = sums.Local();
    vtkNew<vtkIdList> copy;
    double a[3], b[3], c[3];
    for (vtkIdType cellId = c0; cellId < c1; ++cellId) {
      vtkIdType n;
      const vtkIdType* ids;
      if (shared) {
        polys->GetCellAtId(cellId, n, ids);
      } else {
        polys->GetCellAtId(cellId, copy);
        n = copy->GetNumberOfIds(), ids = copy->GetPointer(0);
      }
      if (n < 3) continue;
      view.Get(ids[0], a);
      for (vtkIdType t = 1; t + 1 < n; ++t) {
        view.Get(ids[t], b), view.Get(ids[t + 1], c);
        local[0] += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
        double f[3];
        TriangleCross(a, b, c, f);
        local[1] += 0.5 * std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      }
    }
  });
  for (const auto& local : sums) volume += local[0], area += local[1];
}

}  // namespace rp
