#pragma once
// A planned cut in numbers (plain C++, no VTK): a closed bone surface cut by a plane gives the
// bone volume on each side and the area of the cut. Exact for a closed, consistently oriented
// mesh: each triangle is clipped to the plane's positive side and its signed tetrahedron volume
// summed with the apex on the plane (the cut's own cap then adds nothing), and the cap's area is
// the magnitude along the normal of the clipped triangles' summed vector area (a closed surface's
// vector area is zero, so the cap's is minus the rest).
#include "rpTriangleMesh.h"

namespace rp {

struct CutFigures {
  double VolumeMm3 = 0;           // the whole bone
  double PositiveVolumeMm3 = 0;   // on the normal's side
  double NegativeVolumeMm3 = 0;
  double CutAreaMm2 = 0;          // where the plane crosses the bone
};

CutFigures CutBone(const TriangleMesh& bone, const Vec3& origin, const Vec3& unitNormal) noexcept;

}  // namespace rp
