#pragma once
// What a navigation system tells the surgeon about a tracked tool against a planned trajectory, at
// display rate (plain C++, any thread):
//   entry error      the distance from the planned entry to where the tool's axis crosses the plane
//                    through the entry normal to the plan (the tool's tip's distance from the
//                    planned axis when the tool has no direction or runs parallel to that plane);
//   angle            between the tool's direction and the planned axis (°);
//   depth to target  how much deeper the target lies than the tip, along the plan (mm; < 0: beyond);
//   lateral          the tip's distance from the planned axis (mm);
//   closest structure at risk: its name and the distance from the tool's surface to it (mm).
// These are the score's measures (rpExecutionScore.h) for one pose instead of a whole path. The
// tool's pose is also given in the trajectory's own frame (ToolTipToTrajectory, what the
// OpenIGTLink stream sends; the frame is defined in the Navigation README, "The trajectory's frame").
#include <string>
#include <vector>

#include "rpMeshSignedDistance.h"
#include "rpTrajectoryAxis.h"

namespace rp {

/// The read-out's OpenIGTLink messages (device names): the tool tip in the trajectory's frame
/// (TRANSFORM) and ReadoutString (STRING). The frame is defined in the Navigation README.
constexpr const char* ReadoutTransformName = "ToolTipToTrajectory";
constexpr const char* ReadoutStringName = "GuidanceReadout";

struct ReadoutStructure {
  std::string Name;
  const MeshSignedDistance* Surface = nullptr;  // not owned
  double MarginMm = 0;
};

struct GuidanceReadout {
  bool Valid = false;
  double EntryErrorMm = 0, AngleDeg = 0, DepthToTargetMm = 0, LateralMm = 0;
  bool HasStructure = false;
  std::string ClosestStructure;
  double ClosestStructureMm = 0;
  bool WithinMargin = false;
  double ToolTipToTrajectory[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major
};

/// The trajectory's frame in RAS (row-major 4×4: columns x, y, z and the origin at the entry).
void TrajectoryToRAS(const TrajectoryAxis& plan, double matrix[16]);

/// The read-out for the tool tip `tipToRAS` (row-major 4×4; the tool points along its −z, as the
/// haptic stylus, unless `forward` says otherwise in the tool's frame). `toolRadiusMm` for the
/// clearance to structures (0: the tip itself).
GuidanceReadout ComputeReadout(const TrajectoryAxis& plan, const double tipToRAS[16],
                               const std::vector<ReadoutStructure>& structures, double toolRadiusMm = 0,
                               const Vec3& forward = Vec3{0, 0, -1});

/// The read-out as one line of `key=value;` pairs with units in the keys (the OpenIGTLink STRING):
/// "entryErrorMm=1.23;angleDeg=2.5;depthToTargetMm=10.2;lateralMm=0.8;closestStructure=fibula;closestStructureMm=6.1".
std::string ReadoutString(const GuidanceReadout& readout);

}  // namespace rp
