#pragma once
// What a surgeon checks before cutting, for one trajectory or screw (plain C++, no VTK): length and
// length per tissue with the entries and exits of bone, the CT numbers along the axis and over the
// tool's cross-section, the share of the tool's surface in cortical bone, the cortical breach
// (how far the tool's cylinder stands beyond the bone, graded as Gertzbein and Robbins grade screws)
// and the clearance from each structure at risk. The Planning README says how each is computed.
//
// The tool: a trajectory's drill (entry to target, its tool diameter); a screw's shaft (the
// ScrewLengthMm before the target, the screw's diameter) and head. Depths are mm from the entry
// along the axis (a screw longer than its trajectory starts at a negative depth).
#include <string>
#include <vector>

#include "rpExecutionScore.h"  // GertzbeinRobbinsGrade
#include "rpPlanSnapshot.h"
#include "rpTissueModel.h"

namespace rp {

struct ToolSpan {
  Vec3 Start, End;  // the tool's extent on the axis (End: the target)
  double RadiusMm = 0;
  double StartDepthMm = 0;  // depth of Start from the entry
  Vec3 Direction() const { return Normalized(this->End - this->Start); }
  double LengthMm() const { return Norm(this->End - this->Start); }
};
/// The extent a plan's figures measure: a trajectory's drill, or a screw's shaft.
ToolSpan ToolSpanOf(const TrajectorySnapshot& plan);

struct DepthInterval {
  double FromMm = 0, ToMm = 0;
};

struct TissueLength {
  std::string Name;
  double LengthMm = 0;
  std::vector<DepthInterval> Intervals;
};

struct ProfileSample {
  double DepthMm = 0;
  double HU = 0;                              // on the axis
  double MeanHU = 0, MinHU = 0, MaxHU = 0;    // over the tool's cross-section (a disk)
  bool InBone = false;
};

struct BreachFigure {
  bool Found = false;
  double DepthMm = 0;   // where along the axis the tool stands farthest beyond the bone
  double BreachMm = 0;  // how far (radially from the axis) beyond the bone's boundary
  int Grade = 0;        // Gertzbein-Robbins
  Vec3 Point;           // the point of the tool's surface farthest out
};

struct ClearanceFigure {
  std::string Name;
  double ClearanceMm = 0;  // closest distance from the tool's surface to the structure's (negative: into it)
  double DepthMm = 0;      // where along the axis
  double SafetyMarginMm = 0;
  bool UnderMargin = false;  // ClearanceMm < SafetyMarginMm: red
  bool Crosses = false;      // the tool's axis enters the structure
  Vec3 ToolPoint, StructurePoint;
};

struct TrajectoryFigures {
  double TrajectoryLengthMm = 0;  // entry to target
  double LengthMm = 0;            // the tool's span (a screw: its shaft)
  double ToolDiameterMm = 0;
  double LengthInBoneMm = 0;
  std::vector<DepthInterval> Bone;       // where the axis enters and leaves bone
  std::vector<TissueLength> Tissues;     // per segment (with a segmentation) or bone HU range
  std::vector<TissueLength> BoneByHU;    // the axis in bone, per bone HU range (needs the CT)
  std::vector<ProfileSample> Profile;    // every ProfileStepMm (needs the CT)
  double CorticalSurfaceShare = -1;      // 0..1 of the tool's lateral surface; -1 without a CT
  BreachFigure Breach;
  std::vector<ClearanceFigure> Clearances;
};

struct FigureOptions {
  double ProfileStepMm = 0.5;
  int CrossSectionRings = 4;    // rings of equal area over the tool's disk (96 points)
  int SurfaceAngles = 24;       // around the tool, for the cortical share and the breach
};

TrajectoryFigures ComputeTrajectoryFigures(const TrajectorySnapshot& plan, const TissueModel& tissue,
                                           const std::vector<StructureAtRiskSnapshot>& structures,
                                           const FigureOptions& options = {});

/// Clearance of a tool (its axis segment and radius) from one structure: the BVH's closest
/// segment-to-surface pair, the sign from the structure's closed surface (Signed), the depth of
/// penetration sampled along the axis when it enters. `warmLeaf` as for BVH::ClosestToSegment.
ClearanceFigure ToolClearance(const ToolSpan& tool, const StructureAtRiskSnapshot& structure, double stepMm,
                              uint32_t* warmLeaf = nullptr);

/// Where the axis (from -along to +along beyond the span) is in bone: the intervals of depth.
std::vector<DepthInterval> BoneAlongAxis(const ToolSpan& tool, const TissueModel& tissue, double fromDepthMm,
                                         double toDepthMm);

}  // namespace rp
