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
/// Makes triangles and normals point outward (positive enclosed volume). Returns true when the
/// mesh already was: then the volume and area it measured are the mesh's as it stays, and go to
/// `volume` and `area` when given (a flipped mesh measures a hair differently: measure it anew).
bool OrientOutward(vtkPolyData* mesh, double* volume = nullptr, double* area = nullptr);
/// Moves vertices along their normals until the mesh encloses `targetVolume`; returns the
/// offset (mm).
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume);
/// The same, given the mesh's volume and area as measured (each pass measures anew, so this saves
/// one pass over the triangles); they hold the corrected mesh's on return.
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume, double& volume, double& area);

}  // namespace rp
