#include "rpPolyDataTriangleMesh.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace rp {

bool PolyDataToTriangleMesh(vtkPolyData* polyData, vtkMatrix4x4* toWorld, TriangleMesh& mesh, std::string& error) {
  mesh = TriangleMesh{};
  if (polyData == nullptr || polyData->GetPoints() == nullptr) {
    error = "no points";
    return false;
  }
  const vtkIdType n = polyData->GetNumberOfPoints();
  mesh.Points.resize(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[4] = {0, 0, 0, 1};
    polyData->GetPoint(i, p);
    if (toWorld) toWorld->MultiplyPoint(p, p);
    mesh.Points[static_cast<size_t>(i)] = {p[0], p[1], p[2]};
  }
  vtkIdType count;
  const vtkIdType* ids;
  auto triangle = [&mesh](vtkIdType a, vtkIdType b, vtkIdType c) {
    mesh.Triangles.push_back({static_cast<int32_t>(a), static_cast<int32_t>(b), static_cast<int32_t>(c)});
  };
  if (vtkCellArray* polys = polyData->GetPolys()) {
    mesh.Triangles.reserve(static_cast<size_t>(polys->GetNumberOfCells()));
    auto cells = vtk::TakeSmartPointer(polys->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell()) {
      cells->GetCurrentCell(count, ids);
      for (vtkIdType k = 1; k + 1 < count; ++k) triangle(ids[0], ids[k], ids[k + 1]);
    }
  }
  if (vtkCellArray* strips = polyData->GetStrips()) {
    auto cells = vtk::TakeSmartPointer(strips->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell()) {
      cells->GetCurrentCell(count, ids);
      for (vtkIdType k = 0; k + 2 < count; ++k) {
        if (k % 2 == 0) triangle(ids[k], ids[k + 1], ids[k + 2]);
        else triangle(ids[k + 1], ids[k], ids[k + 2]);
      }
    }
  }
  if (mesh.Triangles.empty()) {
    error = "no polygons";
    return false;
  }
  return mesh.Validate(error);
}

vtkSmartPointer<vtkPolyData> TriangleMeshToPolyData(const TriangleMesh& mesh) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.Points.size()));
  for (size_t i = 0; i < mesh.Points.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), mesh.Points[i].x, mesh.Points[i].y, mesh.Points[i].z);
  vtkNew<vtkCellArray> polys;
  for (const auto& t : mesh.Triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    polys->InsertNextCell(3, ids);
  }
  auto polyData = vtkSmartPointer<vtkPolyData>::New();
  polyData->SetPoints(points);
  polyData->SetPolys(polys);
  return polyData;
}

}  // namespace rp
