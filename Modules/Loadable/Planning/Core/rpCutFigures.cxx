#include "rpCutFigures.h"

#include <cmath>

namespace rp {
namespace {

// The triangle's part on the positive side (distances da, db, dc >= 0 kept): 0, 3 or 4 corners.
int ClipToPositive(const Vec3 p[3], const double d[3], Vec3 out[4]) noexcept {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (d[i] >= 0) out[n++] = p[i];
    if ((d[i] >= 0) != (d[j] >= 0)) out[n++] = p[i] + (p[j] - p[i]) * (d[i] / (d[i] - d[j]));
  }
  return n;
}

}  // namespace

CutFigures CutBone(const TriangleMesh& bone, const Vec3& origin, const Vec3& normal) noexcept {
  CutFigures f;
  Vec3 clippedArea;  // summed vector area (x2) of the positive side's pieces
  double total6 = 0, positive6 = 0;
  for (const auto& t : bone.Triangles) {
    // Relative to the origin: tetrahedra with their apex on the plane.
    const Vec3 p[3] = {bone.Points[static_cast<size_t>(t[0])] - origin, bone.Points[static_cast<size_t>(t[1])] - origin,
                       bone.Points[static_cast<size_t>(t[2])] - origin};
    total6 += Dot(p[0], Cross(p[1], p[2]));
    const double d[3] = {Dot(p[0], normal), Dot(p[1], normal), Dot(p[2], normal)};
    Vec3 piece[4];
    const int n = ClipToPositive(p, d, piece);
    for (int k = 1; k + 1 < n; ++k) {  // a fan over the clipped polygon
      positive6 += Dot(piece[0], Cross(piece[k], piece[k + 1]));
      clippedArea += Cross(piece[k] - piece[0], piece[k + 1] - piece[0]);
    }
  }
  f.VolumeMm3 = total6 / 6;
  f.PositiveVolumeMm3 = positive6 / 6;
  f.NegativeVolumeMm3 = f.VolumeMm3 - f.PositiveVolumeMm3;
  f.CutAreaMm2 = std::fabs(Dot(clippedArea, normal)) / 2;
  return f;
}

}  // namespace rp
