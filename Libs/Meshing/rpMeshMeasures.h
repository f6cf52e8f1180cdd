#pragma once
// What a triangle mesh measures: enclosed volume and area, its edge and vertex topology (holes,
// non-manifold edges and vertices), and the one walk over its triangles that normals, orientation
// checks and sampling share. Plain functions on vtkPolyData, parallel where meshes are large.
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace rp {

/// (b - a) x (c - a): twice the triangle's area along its normal.
inline void TriangleCross(const double a[3], const double b[3], const double c[3], double f[3]) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  f[0] = u[1] * v[2] - u[2] * v[1], f[1] = u[2] * v[0] - u[0] * v[2], f[2] = u[0] * v[1] - u[1] * v[0];
}

/// Points read without a virtual call per coordinate (float or double storage; else vtkPoints).
struct PointsView {
  explicit PointsView(vtkPoints* points) : Points(points) {
    vtkDataArray* data = points->GetData();
    if (auto* f = vtkAOSDataArrayTemplate<float>::FastDownCast(data)) this->F = f->GetPointer(0);
    else if (auto* d = vtkAOSDataArrayTemplate<double>::FastDownCast(data)) this->D = d->GetPointer(0);
  }
  void Get(vtkIdType i, double x[3]) const {
    if (this->F) {
      const float* p = this->F + 3 * i;
      x[0] = p[0], x[1] = p[1], x[2] = p[2];
    } else if (this->D) {
      const double* p = this->D + 3 * i;
      x[0] = p[0], x[1] = p[1], x[2] = p[2];
    } else {
      this->Points->GetPoint(i, x);
    }
  }
  vtkPoints* Points;
  float* F = nullptr;
  double* D = nullptr;
};

/// Calls `visit(ids, a, b, c, cross)` for every triangle (3-point polygon; other cells are
/// skipped) of `mesh`: its corner ids, corner points and TriangleCross(a, b, c). The one walk
/// that vertex normals, orientation checks and area-weighted sampling share.
template <class Visit>
void ForEachTriangle(vtkPolyData* mesh, Visit&& visit) {
  vtkCellArray* polys = mesh->GetPolys();
  vtkPoints* points = mesh->GetPoints();
  if (!polys || !points) return;
  vtkIdType n;
  const vtkIdType* ids;
  double a[3], b[3], c[3], cross[3];
  const PointsView view(points);
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3) continue;
    view.Get(ids[0], a), view.Get(ids[1], b), view.Get(ids[2], c);
    TriangleCross(a, b, c, cross);
    visit(ids, a, b, c, cross);
  }
}

/// Edge topology of a triangle mesh: edges used by one triangle (holes) and by more than two.
void CountBadEdges(vtkPolyData* mesh, long& boundaryEdges, long& nonManifoldEdges);
/// Vertices whose triangles do not form one closed fan (two sheets touching at a point).
long CountNonManifoldVertices(vtkPolyData* mesh);
struct MeshTopology {
  long BoundaryEdges = 0, NonManifoldEdges = 0, NonManifoldVertices = 0;
};
/// All three counts in one parallel pass over every vertex's fan (the edges counted from both
/// ends' fans instead of one global sort of every edge); the same numbers as CountBadEdges and
/// CountNonManifoldVertices.
MeshTopology CountTopology(vtkPolyData* mesh);
/// Enclosed volume (mm³, positive for outward orientation) and area of a triangle mesh.
void MeshVolumeAndArea(vtkPolyData* mesh, double& volume, double& area);



}  // namespace rp
