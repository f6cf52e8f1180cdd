#pragma once
// VTK polydata ↔ rp::TriangleMesh, the plain mesh the BVH, the haptic proxy, the drilling and the
// level-of-detail checks read. One conversion for all of them.
#include <string>

#include <vtkSmartPointer.h>

#include "rpTriangleMesh.h"

class vtkMatrix4x4;
class vtkPolyData;

namespace rp {

/// Triangles of `polyData` (polygons fan-triangulated, strips split; lines and vertices
/// ignored), points mapped by `toWorld` (may be null). False names the problem (no points, no
/// polygons, a bad index). The cells are read with an iterator of its own, not the cell array's
/// traversal cursor, so another thread may read the same polydata meanwhile.
bool PolyDataToTriangleMesh(vtkPolyData* polyData, vtkMatrix4x4* toWorld, TriangleMesh& mesh, std::string& error);

/// A vtkPolyData (points + triangles) of a mesh, e.g. to put an analytic shape into a model node.
vtkSmartPointer<vtkPolyData> TriangleMeshToPolyData(const TriangleMesh& mesh);

}  // namespace rp
