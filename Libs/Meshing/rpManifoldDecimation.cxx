#include "rpManifoldDecimation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <queue>
#include <vector>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "rpLabelmapToMesh.h"

namespace rp {

namespace {

using Vec = std::array<double, 3>;
using Quadric = std::array<double, 10>;  // upper triangle of the 4x4 symmetric matrix

Vec Sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec Cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

double Evaluate(const Quadric& q, const Vec& p) {
  const double x = p[0], y = p[1], z = p[2];
  return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z +
         2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
}

struct Candidate {
  double Cost;
  int32_t U, V;
  uint32_t VersionU, VersionV;
  Vec Position;
  bool operator<(const Candidate& o) const { return this->Cost > o.Cost; }  // min-heap
};

class Decimator {
 public:
  std::vector<Vec> P;
  std::vector<std::array<int32_t, 3>> T;
  std::vector<char> TriangleAlive;
  std::vector<std::vector<int32_t>> VertexTriangles;
  std::vector<Quadric> Q;
  std::vector<uint32_t> Version;
  long Alive = 0;

  void Build() {
    this->VertexTriangles.assign(this->P.size(), {});
    this->Q.assign(this->P.size(), Quadric{});
    this->Version.assign(this->P.size(), 0);
    this->TriangleAlive.assign(this->T.size(), 1);
    this->Alive = static_cast<long>(this->T.size());
    for (size_t t = 0; t < this->T.size(); ++t) {
      const auto& tri = this->T[t];
      Vec n = Cross(Sub(this->P[tri[1]], this->P[tri[0]]), Sub(this->P[tri[2]], this->P[tri[0]]));
      const double len = std::sqrt(Dot(n, n));
      if (len > 0) n = {n[0] / len, n[1] / len, n[2] / len};
      const double d = -Dot(n, this->P[tri[0]]);
      const Quadric k = {n[0] * n[0], n[0] * n[1], n[0] * n[2], n[0] * d, n[1] * n[1],
                         n[1] * n[2], n[1] * d,    n[2] * n[2], n[2] * d, d * d};
      for (int32_t v : tri) {
        this->VertexTriangles[static_cast<size_t>(v)].push_back(static_cast<int32_t>(t));
        for (int i = 0; i < 10; ++i) this->Q[static_cast<size_t>(v)][static_cast<size_t>(i)] += k[static_cast<size_t>(i)];
      }
    }
  }

  // Alive triangles around v (pruned in place).
  std::vector<int32_t>& Around(int32_t v) {
    auto& list = this->VertexTriangles[static_cast<size_t>(v)];
    list.erase(std::remove_if(list.begin(), list.end(), [&](int32_t t) { return !this->TriangleAlive[static_cast<size_t>(t)]; }),
               list.end());
    return list;
  }

  void Neighbours(int32_t v, std::vector<int32_t>& out) {
    out.clear();
    for (int32_t t : this->Around(v))
      for (int32_t w : this->T[static_cast<size_t>(t)])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  Candidate Evaluate(int32_t u, int32_t v) {
    Quadric q;
    for (size_t i = 0; i < 10; ++i) q[i] = this->Q[static_cast<size_t>(u)][i] + this->Q[static_cast<size_t>(v)][i];
    const Vec& a = this->P[static_cast<size_t>(u)];
    const Vec& b = this->P[static_cast<size_t>(v)];
    const Vec mid = {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    Candidate c{rp::Evaluate(q, mid), u, v, this->Version[static_cast<size_t>(u)], this->Version[static_cast<size_t>(v)], mid};
    for (const Vec* p : {&a, &b}) {
      const double e = rp::Evaluate(q, *p);
      if (e < c.Cost) c.Cost = e, c.Position = *p;
    }
    // The quadric's minimum when well conditioned and near the edge.
    const double m[3][3] = {{q[0], q[1], q[2]}, {q[1], q[4], q[5]}, {q[2], q[5], q[7]}};
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    const double scale = q[0] + q[4] + q[7];
    if (std::abs(det) > 1e-9 * scale * scale * scale) {
      const double r[3] = {-q[3], -q[6], -q[8]};
      Vec x;
      for (int i = 0; i < 3; ++i) {
        double mi[3][3];
        for (int row = 0; row < 3; ++row)
          for (int col = 0; col < 3; ++col) mi[row][col] = col == i ? r[row] : m[row][col];
        x[static_cast<size_t>(i)] = (mi[0][0] * (mi[1][1] * mi[2][2] - mi[1][2] * mi[2][1]) -
                                     mi[0][1] * (mi[1][0] * mi[2][2] - mi[1][2] * mi[2][0]) +
                                     mi[0][2] * (mi[1][0] * mi[2][1] - mi[1][1] * mi[2][0])) / det;
      }
      const Vec edge = Sub(b, a);
      const Vec off = Sub(x, mid);
      if (Dot(off, off) <= Dot(edge, edge)) {
        const double e = rp::Evaluate(q, x);
        if (e < c.Cost) c.Cost = e, c.Position = x;
      }
    }
    c.Cost = std::max(0.0, c.Cost);
    return c;
  }

  // The checks of the header; true when collapsing v into u at `p` keeps the surface a manifold.
  bool Allowed(int32_t u, int32_t v, const Vec& p) {
    std::vector<int32_t> nu, nv, common;
    this->Neighbours(u, nu);
    this->Neighbours(v, nv);
    std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
    if (common.size() != 2) return false;
    std::vector<int32_t> tmp;
    for (int32_t w : common) {
      this->Neighbours(w, tmp);
      if (tmp.size() <= 3) return false;
    }
    for (int32_t x : {u, v})
      for (int32_t t : this->Around(x)) {
        const auto& tri = this->T[static_cast<size_t>(t)];
        const bool hasU = tri[0] == u || tri[1] == u || tri[2] == u;
        const bool hasV = tri[0] == v || tri[1] == v || tri[2] == v;
        if (hasU && hasV) continue;  // dies
        Vec before[3], after[3];
        for (int k = 0; k < 3; ++k) {
          before[k] = this->P[static_cast<size_t>(tri[static_cast<size_t>(k)])];
          after[k] = (tri[static_cast<size_t>(k)] == u || tri[static_cast<size_t>(k)] == v) ? p : before[k];
        }
        const Vec n0 = Cross(Sub(before[1], before[0]), Sub(before[2], before[0]));
        const Vec n1 = Cross(Sub(after[1], after[0]), Sub(after[2], after[0]));
        const double l0 = std::sqrt(Dot(n0, n0)), l1 = std::sqrt(Dot(n1, n1));
        if (l1 <= 1e-12 * (l0 + 1e-30) || Dot(n0, n1) < 0.2 * l0 * l1) return false;
      }
    return true;
  }

  void Collapse(int32_t u, int32_t v, const Vec& p) {
    for (int32_t t : std::vector<int32_t>(this->Around(v))) {
      auto& tri = this->T[static_cast<size_t>(t)];
      const bool hasU = tri[0] == u || tri[1] == u || tri[2] == u;
      if (hasU) {
        this->TriangleAlive[static_cast<size_t>(t)] = 0;
        --this->Alive;
        continue;
      }
      for (auto& w : tri)
        if (w == v) w = u;
      this->VertexTriangles[static_cast<size_t>(u)].push_back(t);
    }
    this->VertexTriangles[static_cast<size_t>(v)].clear();
    this->P[static_cast<size_t>(u)] = p;
    for (size_t i = 0; i < 10; ++i) this->Q[static_cast<size_t>(u)][i] += this->Q[static_cast<size_t>(v)][i];
    ++this->Version[static_cast<size_t>(u)];
    ++this->Version[static_cast<size_t>(v)];
  }
};

}  // namespace

bool DecimateManifold(vtkPolyData* mesh, long targetTriangles, double maxErrorMm, DecimationResult& result) {
  result = DecimationResult();
  if (!mesh || !mesh->GetPoints() || mesh->GetNumberOfPolys() == 0) return false;
  const MeshTopology topology = CountTopology(mesh);
  if (topology.BoundaryEdges || topology.NonManifoldEdges || topology.NonManifoldVertices) return false;
  Decimator d;
  d.P.resize(static_cast<size_t>(mesh->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) mesh->GetPoint(i, d.P[static_cast<size_t>(i)].data());
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = mesh->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3) return false;
    d.T.push_back({static_cast<int32_t>(ids[0]), static_cast<int32_t>(ids[1]), static_cast<int32_t>(ids[2])});
  }
  d.Build();
  result.TrianglesBefore = d.Alive;
  std::priority_queue<Candidate> heap;
  for (const auto& tri : d.T)
    for (int e = 0; e < 3; ++e) {
      const int32_t a = tri[static_cast<size_t>(e)], b = tri[static_cast<size_t>((e + 1) % 3)];
      if (a < b) heap.push(d.Evaluate(a, b));  // each edge once (the other triangle has b, a)
    }
  const double maxCost = maxErrorMm > 0 ? maxErrorMm * maxErrorMm : std::numeric_limits<double>::max();
  std::vector<int32_t> neighbours;
  while (d.Alive > targetTriangles && !heap.empty()) {
    const Candidate c = heap.top();
    heap.pop();
    if (c.VersionU != d.Version[static_cast<size_t>(c.U)] || c.VersionV != d.Version[static_cast<size_t>(c.V)]) continue;
    if (c.Cost > maxCost) break;
    if (!d.Allowed(c.U, c.V, c.Position)) continue;
    d.Collapse(c.U, c.V, c.Position);
    result.MaxQuadricErrorMm = std::max(result.MaxQuadricErrorMm, std::sqrt(c.Cost));
    d.Neighbours(c.U, neighbours);
    for (int32_t w : neighbours) heap.push(d.Evaluate(c.U, w));
  }
  result.TrianglesAfter = d.Alive;
  result.TargetReached = d.Alive <= targetTriangles;
  // Compact: used vertices only.
  std::vector<vtkIdType> index(d.P.size(), -1);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(d.Alive, 3 * d.Alive);
  for (size_t t = 0; t < d.T.size(); ++t) {
    if (!d.TriangleAlive[t]) continue;
    vtkIdType tri[3];
    for (int k = 0; k < 3; ++k) {
      const size_t v = static_cast<size_t>(d.T[t][static_cast<size_t>(k)]);
      if (index[v] < 0) index[v] = points->InsertNextPoint(d.P[v].data());
      tri[k] = index[v];
    }
    cells->InsertNextCell(3, tri);
  }
  mesh->Initialize();
  mesh->SetPoints(points);
  mesh->SetPolys(cells);
  return true;
}

}  // namespace rp
