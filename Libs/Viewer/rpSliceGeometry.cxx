#include "rpSliceGeometry.h"

#include <cmath>

#include <vtkMath.h>

#include "vtkRPSliceNode.h"

namespace rp {

bool IsSliceView(ViewKind kind) { return kind != ViewKind::ThreeD; }

SliceAxes GetSliceAxes(ViewKind kind) {
  // The frames are the scene's (vtkRPSliceNode), defined once.
  double m[3][3];
  vtkRPSliceNode::GetOrientationMatrix(GetViewName(kind == ViewKind::ThreeD ? ViewKind::Axial : kind), m);
  SliceAxes axes{};
  for (int r = 0; r < 3; ++r) {
    axes.X[r] = m[r][0];
    axes.Y[r] = m[r][1];
    axes.Normal[r] = m[r][2];
    if (std::fabs(m[r][2]) > 0.5) axes.NormalAxis = r;
  }
  return axes;
}

void GetCameraDirection(ViewKind kind, double towardsCamera[3]) {
  SliceAxes axes = GetSliceAxes(kind);
  vtkMath::Cross(axes.X, axes.Y, towardsCamera);
}

const char* GetViewName(ViewKind kind) {
  switch (kind) {
    case ViewKind::Axial: return "Axial";
    case ViewKind::Sagittal: return "Sagittal";
    case ViewKind::Coronal: return "Coronal";
    default: return "3D";
  }
}

void GetViewColor(ViewKind kind, double rgb[3]) {
  static const double colors[4][3] = {{0.95, 0.33, 0.27}, {0.93, 0.84, 0.30}, {0.43, 0.69, 0.29}, {0.6, 0.6, 0.9}};
  const double* c = colors[static_cast<int>(kind)];
  rgb[0] = c[0];
  rgb[1] = c[1];
  rgb[2] = c[2];
}

}  // namespace rp
