#include "rpSliceGeometry.h"

namespace rp {

bool IsSliceView(ViewKind kind) { return kind != ViewKind::ThreeD; }

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
