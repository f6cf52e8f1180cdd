#pragma once
// A screw's closed surface placed along its plan (plain C++): a surface of revolution about the
// axis, its tip at the target (a cone one radius long), the shaft back towards the entry for the
// screw's length, then the head (a cylinder of the head's diameter and length). Closed, manifold,
// outward triangles: it can be a model, a haptic surface or a structure to measure against.
#include "rpPlanSnapshot.h"
#include "rpTriangleMesh.h"

namespace rp {

/// `segments` around the axis (>= 3).
TriangleMesh MakeScrewMesh(const TrajectorySnapshot& screw, int segments = 32);

}  // namespace rp
