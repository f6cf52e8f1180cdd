#pragma once
// Steps that move or re-orient a contoured surface: grid coordinates to RAS, area-weighted vertex
// normals, outward orientation, and the volume correction that makes a mesh enclose a given volume.
#include <vtkPolyData.h>

class vtkMatrix4x4;

namespace rp {

/// Points (grid index p) → RAS: ras = M * (start + p * step). Normals given as gradients in grid
/// coordinates (haveGridNormals) go through the inverse transpose and are normalized.
void GridToRAS(vtkPolyData* mesh, const vtkMatrix4x4* ijkToRAS, const double start[3], const double step[3],
               bool haveGridNormals);
/// Area-weighted vertex normals (outward for an outward-oriented mesh), point data "Normals".
void ComputeMeshNormals(vtkPolyData* mesh);
/// Makes triangles and normals point outward (positive enclosed volume).
void OrientOutward(vtkPolyData* mesh);
/// Moves vertices along their normals until the mesh encloses `targetVolume`; returns the
/// offset (mm).
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume);

}  // namespace rp
