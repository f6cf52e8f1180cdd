#include "rpGuidanceReadout.h"

#include <cmath>
#include <cstdio>

namespace rp {

void TrajectoryToRAS(const TrajectoryAxis& plan, double m[16]) {
  const Vec3 z = plan.Direction();
  // x: the patient's right across the axis; anterior when the plan itself runs along R.
  Vec3 x = Vec3{1, 0, 0} - z * z.x;
  if (Norm(x) < 0.1) x = Vec3{0, 1, 0} - z * z.y;
  x = Normalized(x);
  const Vec3 y = Cross(z, x);
  const Vec3& o = plan.Entry();
  const double rows[16] = {x.x, y.x, z.x, o.x, x.y, y.y, z.y, o.y, x.z, y.z, z.z, o.z, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) m[i] = rows[i];
}

GuidanceReadout ComputeReadout(const TrajectoryAxis& plan, const double t[16], const std::vector<ReadoutStructure>& structures,
                               double toolRadiusMm, const Vec3& forward) {
  GuidanceReadout r;
  if (!(plan.Length() > 0)) return r;
  const Vec3 tip{t[3], t[7], t[11]};
  const Vec3 direction = Normalized(Vec3{t[0] * forward.x + t[1] * forward.y + t[2] * forward.z,
                                         t[4] * forward.x + t[5] * forward.y + t[6] * forward.z,
                                         t[8] * forward.x + t[9] * forward.y + t[10] * forward.z});
  r.Valid = true;
  r.LateralMm = plan.Distance(tip);
  r.DepthToTargetMm = plan.Length() - plan.Depth(tip);
  r.AngleDeg = AngleBetweenDegrees(direction, plan.Direction());
  Vec3 crossing;
  const bool crosses = Norm2(direction) > 0 && std::fabs(Dot(direction, plan.Direction())) > 1e-6 &&
                       LinePlaneIntersection(tip, direction, plan.Entry(), plan.Direction(), crossing);
  r.EntryErrorMm = crosses ? Norm(crossing - plan.Entry()) : r.LateralMm;
  for (const ReadoutStructure& s : structures) {
    if (!s.Surface || s.Surface->Empty()) continue;
    const double d = s.Surface->SignedDistance(tip) - toolRadiusMm;
    if (!r.HasStructure || d < r.ClosestStructureMm) {
      r.HasStructure = true;
      r.ClosestStructure = s.Name;
      r.ClosestStructureMm = d;
      r.WithinMargin = d < s.MarginMm;
    }
  }
  // ToolTipToTrajectory = (TrajectoryToRAS)^-1 · ToolTipToRAS: the inverse of a rigid frame is its transpose.
  double f[16];
  TrajectoryToRAS(plan, f);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) {
      double v = 0;
      for (int k = 0; k < 3; ++k) v += f[4 * k + row] * (t[4 * k + col] - (col == 3 ? f[4 * k + 3] : 0.0));
      r.ToolTipToTrajectory[4 * row + col] = v;
    }
  }
  return r;
}

std::string ReadoutString(const GuidanceReadout& r) {
  if (!r.Valid) return "valid=0";
  char line[512];
  std::snprintf(line, sizeof line, "entryErrorMm=%.3f;angleDeg=%.3f;depthToTargetMm=%.3f;lateralMm=%.3f", r.EntryErrorMm,
                r.AngleDeg, r.DepthToTargetMm, r.LateralMm);
  std::string out = line;
  if (r.HasStructure) {
    std::snprintf(line, sizeof line, ";closestStructure=%s;closestStructureMm=%.3f;withinMargin=%d", r.ClosestStructure.c_str(),
                  r.ClosestStructureMm, r.WithinMargin ? 1 : 0);
    out += line;
  }
  return out;
}

}  // namespace rp
