#include "rpSurfaceCorrection.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSMPTools.h>

#include "rpMeshMeasures.h"

namespace rp {

void GridToRAS(vtkPolyData* mesh, const vtkMatrix4x4* ijkToRAS, const double start[3], const double step[3],
               bool haveGridNormals) {
  double m[3][4], nm[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = ijkToRAS->GetElement(r, c);
  vtkNew<vtkMatrix4x4> inverse;
  vtkMatrix4x4::Invert(const_cast<vtkMatrix4x4*>(ijkToRAS), inverse);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) nm[r][c] = inverse->GetElement(c, r) / step[c];  // (M^-T) * diag(1/step)
  vtkPoints* points = mesh->GetPoints();
  vtkDataArray* normals = haveGridNormals ? mesh->GetPointData()->GetNormals() : nullptr;
  vtkSMPTools::For(0, mesh->GetNumberOfPoints(), [&](vtkIdType p0, vtkIdType p1) {
    double p[3], q[3], n[3];
    for (vtkIdType id = p0; id < p1; ++id) {
      points->GetPoint(id, p);
      for (int a = 0; a < 3; ++a) p[a] = start[a] + p[a] * step[a];
      for (int r = 0; r < 3; ++r) q[r] = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
      points->SetPoint(id, q);
      if (!normals) continue;
      normals->GetTuple(id, p);
      for (int r = 0; r < 3; ++r) n[r] = nm[r][0] * p[0] + nm[r][1] * p[1] + nm[r][2] * p[2];
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0) n[0] /= len, n[1] /= len, n[2] /= len;
      normals->SetTuple(id, n);
    }
  });
}

void ComputeMeshNormals(vtkPolyData* mesh) {
  const vtkIdType np = mesh->GetNumberOfPoints();
  std::vector<double> acc(static_cast<size_t>(np) * 3, 0.0);
  ForEachTriangle(mesh, [&](const vtkIdType* ids, const double*, const double*, const double*, const double* f) {
    for (int t = 0; t < 3; ++t)
      for (int d = 0; d < 3; ++d) acc[static_cast<size_t>(ids[t]) * 3 + d] += f[d];
  });
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(np);
  for (vtkIdType id = 0; id < np; ++id) {
    double* v = &acc[static_cast<size_t>(id) * 3];
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0) v[0] /= len, v[1] /= len, v[2] /= len;
    normals->SetTuple(id, v);
  }
  mesh->GetPointData()->SetNormals(normals);
}

bool OrientOutward(vtkPolyData* mesh, double* measuredVolume, double* measuredArea) {
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  if (measuredVolume) *measuredVolume = volume;
  if (measuredArea) *measuredArea = area;
  const bool wasOutward = volume >= 0;
  if (volume < 0) {
    vtkCellArray* polys = mesh->GetPolys();
    vtkNew<vtkCellArray> flipped;
    flipped->AllocateExact(polys->GetNumberOfCells(), polys->GetNumberOfConnectivityIds());
    vtkIdType n;
    const vtkIdType* ids;
    std::vector<vtkIdType> reversed;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
      reversed.assign(ids, ids + n);
      std::reverse(reversed.begin(), reversed.end());
      flipped->InsertNextCell(n, reversed.data());
    }
    mesh->SetPolys(flipped);
  }
  // Normals must agree with the (now outward) triangles: compare with face normals in bulk.
  vtkDataArray* normals = mesh->GetPointData()->GetNormals();
  if (!normals) return wasOutward;
  double agreement = 0, nv[3];
  ForEachTriangle(mesh, [&](const vtkIdType* ids, const double*, const double*, const double*, const double* f) {
    normals->GetTuple(ids[0], nv);
    agreement += f[0] * nv[0] + f[1] * nv[1] + f[2] * nv[2];
  });
  if (agreement < 0) {
    for (vtkIdType id = 0; id < normals->GetNumberOfTuples(); ++id) {
      normals->GetTuple(id, nv);
      nv[0] = -nv[0], nv[1] = -nv[1], nv[2] = -nv[2];
      normals->SetTuple(id, nv);
    }
  }
  return wasOutward;
}

// Moves vertices along their normals so the enclosed volume becomes `targetVolume`. The
// first-order offset (dV / area) misses the curvature term, so it iterates a few times.
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume) {
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  return CorrectMeshVolume(mesh, targetVolume, volume, area);
}

double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume, double& volume, double& area) {
  vtkDataArray* normals = mesh->GetPointData()->GetNormals();
  if (area <= 0 || !normals) return 0;
  double total = 0;
  for (int pass = 0; pass < 8 && std::abs(targetVolume - volume) > 1e-5 * targetVolume; ++pass) {
    const double offset = (targetVolume - volume) / area;
    vtkPoints* points = mesh->GetPoints();
    const PointsView view(points);
    vtkSMPTools::For(0, mesh->GetNumberOfPoints(), [&](vtkIdType b, vtkIdType e) {
      double p[3], n[3];
      for (vtkIdType id = b; id < e; ++id) {
        normals->GetTuple(id, n);
        if (view.F) {
          for (int a = 0; a < 3; ++a) view.F[3 * id + a] += static_cast<float>(offset * n[a]);
        } else if (view.D) {
          for (int a = 0; a < 3; ++a) view.D[3 * id + a] += offset * n[a];
        } else {
          view.Get(id, p);
          for (int a = 0; a < 3; ++a) p[a] += offset * n[a];
          points->SetPoint(id, p);
        }
      }
    });
    points->Modified();
    total += offset;
    MeshVolumeAndArea(mesh, volume, area);
  }
  return total;
}

}  // namespace rp
