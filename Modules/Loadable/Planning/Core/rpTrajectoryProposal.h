#pragma once
// Proposing a trajectory (plain C++, no VTK): given a target, entry candidates (the points of an
// entry region) and the structures at risk, the clearance of every candidate's tool from every
// structure (the BVH's segment query, warm-started from the neighbouring candidate's closest
// triangle, on worker threads), whether it stays in bone, and the best few, far enough apart to be
// real alternatives. A candidate's score is its smallest clearance beyond the structure's safety
// margin ("slack"); the best have the largest slack. The risk map is every candidate's clearance.
#include <cstdint>
#include <string>
#include <vector>

#include "rpPlanSnapshot.h"
#include "rpTissueModel.h"

namespace rp {

struct ProposalRequest {
  Vec3 Target;
  double ToolDiameterMm = 2;
  std::vector<Vec3> Candidates;  // entry points
  /// Refuse candidates whose axis leaves the bone between its first entry into bone and the
  /// target (checked on the axis and four lines of the tool's surface every `BoneStepMm`).
  bool StayInBone = false;
  double BoneStepMm = 0.5;
  int Best = 5;
  /// Best candidates at least this far apart (mm); 0: three times the candidates' spacing.
  double MinimumSeparationMm = 0;
  int Threads = 2;
  /// Optional, for repeated proposals over the same candidates (dragging the target): their
  /// SpatialOrder and MedianSpacing, computed once.
  const std::vector<uint32_t>* Order = nullptr;
  double SpacingMm = 0;
};

struct CandidateScore {
  float ClearanceMm = 0;  // clearance from the structure that limits this entry (HUGE_VAL without structures)
  float SlackMm = 0;      // smallest clearance beyond a structure's margin: the score
  float DepthMm = 0;      // where along that candidate's axis (from its entry)
  int16_t Structure = -1;  // which structure is closest
  bool InBone = true;      // stays in bone (always true unless StayInBone was asked)
  bool Valid = true;       // not degenerate (an entry at the target)
};

struct ProposalResult {
  std::vector<CandidateScore> Scores;  // one per candidate, in the request's order
  std::vector<int> Best;               // candidate indices, best first
  double SpacingMm = 0;                // median distance to the nearest other candidate
  double Seconds = 0;                  // wall time of the scoring
  std::string Error;
};

/// Scores every candidate and picks the best. `tissue` may be null unless StayInBone.
ProposalResult ProposeTrajectory(const ProposalRequest& request, const std::vector<StructureAtRiskSnapshot>& structures,
                                 const TissueModel* tissue);

/// The candidates' order along a Morton curve (neighbours in space are neighbours in the list:
/// the warm start of one query is close to the next answer).
std::vector<uint32_t> SpatialOrder(const std::vector<Vec3>& points);

/// Median distance from a point to its nearest other point (a grid of buckets; O(n)).
double MedianSpacing(const std::vector<Vec3>& points);

}  // namespace rp
