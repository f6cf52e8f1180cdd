#pragma once
// `roboplan drill`: a headless drilling stroke for tests and scripts, through the Drilling
// module's logic (vtkRPDrillingLogic) as the panel and the demo drill.
//   roboplan drill [--block | <segmentation> --segment ID] --burr-radius MM --from R,A,S --to R,A,S
//                  --speed MM/S [--voxel MM] [--protect ID] [--ct FILE] [--record FILE]
//                  [--replay FILE] [--model FILE] [--picture FILE] [--realtime] [--json]
// The burr starts at --from (cutting) and is pushed towards --to at --speed by a simulated
// device; the run ends when the burr reaches --to, a protected structure stops it, or the time
// runs out. Reports the removed volume per tissue (and, for --block, the analytic volume of
// the stroke), servo tick and dirty-block re-contour timings, the peak force.
#include <ostream>
#include <string>
#include <vector>

#include "rpDrillVolume.h"

class vtkRPScene;

namespace rp {

/// Parse → vtkRPDrillingLogic (the bone, the stroke) → report. `scene` may be null (a scene of its
/// own is used); the drilled bone's model node is added to it.
int RunDrillCommand(const std::vector<std::string>& args, vtkRPScene* scene, std::ostream& out, std::ostream& err);

/// Volume of the capsule (segment a–b, radius r) inside the axis-aligned box: closed form when
/// it lies wholly inside (πr²L + 4/3·πr³), else integrated numerically. `exact` says which.
double CapsuleVolumeInBox(const Vec3& a, const Vec3& b, double r, const Vec3& lo, const Vec3& hi, bool& exact);

/// Largest distance (mm) from a path (the burr centres of a run, decimated to 0.05 mm steps here;
/// or a straight stroke {a, b}) of a voxel whose density differs from the bone as built (0 when
/// nothing changed).
double FarthestChangeFromPath(const DrillVolume& volume, const std::vector<Vec3>& path);

}  // namespace rp
