#pragma once
// An execution (a drilled tunnel, a recorded burr or tool-tip path) scored against its planned
// trajectory with the measures surgeons report:
//   executed axis  the least-squares line through the path, resampled every 0.1 mm of its length
//                  (so where the tool dwelt does not weigh more), pointing the way it was drilled;
//   entry offset   the distance from the planned entry to where the executed axis crosses the
//                  plane through the entry normal to the plan (mm); tip offset the same at the target;
//   angle          between the executed and the planned axis (°);
//   depth error    the deepest point of the path along the planned axis minus the target's depth
//                  (mm; > 0: beyond the target, < 0: short of it);
//   max deviation  the farthest any point of the path was from the planned axis, from the entry
//                  plane on (the approach to the entry is not scored; beyond the target is);
//   deviation along depth: the farthest from the planned axis in each 0.5 mm of depth (the chart);
//   breach         how far the tool (radius r) came out of the bone where the plan runs inside it
//                  (from r past the planned entry into bone to r before the planned exit or the
//                  target), and its Gertzbein–Robbins grade (0: none, 1: < 2 mm, 2: 2–4, 3: 4–6, 4: > 6);
//   clearance      per structure at risk, the closest the tool's surface came to it, and where;
//   outside volume the volume drilled outside the plan's cylinder (radius: half the plan's diameter,
//                  between the entry and target planes): from the bone removed (a drilling run's
//                  voxels) or, for a path alone, from the swept tool voxelized (inside the bone when
//                  one is given).
// Plain C++ on the project's geometry (no VTK).
#include <string>
#include <vector>

#include "rpMeshSignedDistance.h"
#include "rpTrajectoryAxis.h"

namespace rp {

/// Gertzbein–Robbins grade of a breach depth (mm beyond the cortex): 0 none, 1 under 2 mm, 2
/// 2–4 mm, 3 4–6 mm, 4 over 6 mm (the grade spine surgeons give screws; exactly 2 mm is grade 2,
/// exactly 4 mm grade 3, exactly 6 mm grade 3). The one definition: planning's figures and the
/// execution score both grade with it.
int GertzbeinRobbinsGrade(double breachMm) noexcept;

/// A structure at risk the execution is measured against.
struct ScoredStructure {
  std::string Name;
  const MeshSignedDistance* Surface = nullptr;  // closed surface (not owned)
  double MarginMm = 0;
};

/// Material an execution removed: a voxel's centre and how much of it went (mm³).
struct RemovedVoxel {
  Vec3 Center;
  double VolumeMm3 = 0;
};

struct ExecutionInput {
  TrajectoryAxis Plan;
  double PlanDiameterMm = 0;     // the planned tool's diameter (the cylinder of the outside volume)
  double ToolRadiusMm = 0;       // the executing tool's radius (a burr's; 0: a stylus tip)
  std::vector<Vec3> Path;        // tool points in the order drilled (RAS mm)
  const MeshSignedDistance* Bone = nullptr;  // for the breach (and the swept volume's bone); optional
  std::vector<ScoredStructure> Structures;
  /// The removed material when known (a drilling run); empty: the swept tool along the path.
  std::vector<RemovedVoxel> Removed;
  double SweepVoxelMm = 0.1;     // the swept tool's voxels (when Removed is empty and ToolRadiusMm > 0)
  double DeviationBinMm = 0.5;   // the chart's depth bins
};

struct StructureClearance {
  std::string Name;
  double ClosestMm = 0;   // tool surface to structure surface (negative: inside it)
  double DepthMm = 0;     // where, along the planned axis
  double MarginMm = 0;
  bool WithinMargin = false;
};

struct DeviationSample {
  double DepthMm = 0, DeviationMm = 0;
};

struct ExecutionScore {
  double EntryOffsetMm = 0, TipOffsetMm = 0, AngleDeg = 0, DepthErrorMm = 0, MaxDeviationMm = 0;
  Vec3 ExecutedEntry, ExecutedTip, ExecutedDirection;  // the executed axis at the planned entry and target planes
  bool HasBreach = false;  // a bone was given
  double BreachMm = 0;
  double BreachDepthMm = 0;
  int BreachGrade = 0;
  std::vector<StructureClearance> Clearance;
  bool HasVolume = false;  // removed voxels given, or a tool radius to sweep
  double DrilledVolumeMm3 = 0, OutsideVolumeMm3 = 0;
  std::vector<DeviationSample> DeviationAlongDepth;
  size_t Points = 0;
  double PathLengthMm = 0;
};

/// False with `error` naming the problem (fewer than two distinct points, a path parallel to the
/// plan's entry plane, ...).
bool ScoreExecution(const ExecutionInput& input, ExecutionScore& score, std::string& error);

/// The path every `spacing` mm of its length (its first and last points kept).
std::vector<Vec3> ResampleByLength(const std::vector<Vec3>& path, double spacing);

}  // namespace rp
