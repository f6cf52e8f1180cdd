#pragma once
// A plan's figures as JSON, with the units in the key names (lengthMm, clearanceMm, ...): what
// `roboplan plan --json` prints and the demo's report holds. One place for the keys.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"
#include "vtkRPPlanningLogic.h"

namespace rp {

nlohmann::json PointJson(const Vec3& p);
/// The plan itself: name, entry, target, tool diameter (a screw: its sizes too).
nlohmann::json TrajectoryJson(const TrajectorySnapshot& plan, const std::string& intendedTissue);
/// lengthMm, lengthInBoneMm, bone, tissues, boneByDensity, profile, corticalSurfaceShare, breach,
/// clearance (see the Planning README).
nlohmann::json FiguresJson(const TrajectoryFigures& figures, const TissueModel& tissue);
/// best (entry, clearanceMm, slackMm, ...), candidates, candidateSpacingMm, seconds.
nlohmann::json ProposalJson(const ProposalRequest& request, const ProposalResult& result,
                            const std::vector<StructureAtRiskSnapshot>& structures);
nlohmann::json CutJson(const std::vector<vtkRPPlanningLogic::BoneCut>& cuts);

}  // namespace rp
