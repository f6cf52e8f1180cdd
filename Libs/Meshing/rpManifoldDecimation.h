#pragma once
// Topology-preserving decimation of a closed manifold triangle mesh: quadric-error edge
// collapses (Garland & Heckbert 1997) that are refused whenever they could change the topology
// or fold the surface: the link condition (the edge's end points share exactly its two
// opposite vertices), no opposite vertex of valence 3 (a tetrahedron or a fin would collapse
// flat), no triangle turned over or made degenerate. A closed manifold stays closed and
// manifold at every step, so it converges to any target down to a few triangles per
// component (a tetrahedron each). vtkQuadricDecimation guarantees none of this.
class vtkPolyData;

namespace rp {

struct DecimationResult {
  long TrianglesBefore = 0, TrianglesAfter = 0;
  bool TargetReached = false;  // false: stopped by the error bound or nothing left to collapse
  double MaxQuadricErrorMm = 0;  // sqrt of the largest quadric cost accepted (~ distance to the planes)
};

/// Decimates `mesh` in place (triangles only; point data is dropped) to at most
/// `targetTriangles`, never accepting a collapse whose quadric error exceeds `maxErrorMm`
/// (0 = no bound). Returns false, leaving the mesh untouched, when it is not a closed
/// manifold triangle mesh.
bool DecimateManifold(vtkPolyData* mesh, long targetTriangles, double maxErrorMm, DecimationResult& result);

}  // namespace rp
