#pragma once
// A plan's pictures for the report, the CLI and the panel: the HU profile chart (CT numbers against
// depth along the axis and over the tool's cross-section, with the bone ranges of materials.json
// marked) and the risk map (the entry region coloured by clearance, with the structures at risk,
// the target and the best trajectories). PNGs drawn offscreen (Libs/Charts; the risk map by
// libRoboPlanPlanningPictures.so, loaded when one is drawn).
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"

class vtkPolyData;

namespace rp {

bool WriteProfileChart(const std::string& path, const TrajectoryFigures& figures, const TissueModel& tissue,
                       const std::string& planName, std::string& error);

/// `riskMap` carries the point scalar "clearanceMm" (vtkRPPlanningLogic::RiskMapPolyData). Drawn by
/// libRoboPlanPlanningPictures.so (Pictures/rpRiskMapPicture.cxx), loaded on the first picture;
/// false with `error` naming that file where it is missing.
bool WriteRiskMapPicture(const std::string& path, vtkPolyData* riskMap, const std::vector<StructureAtRiskSnapshot>& structures,
                         const double target[3], const std::vector<Vec3>& candidates, const ProposalResult& result,
                         std::string& error);

/// The library that draws the risk map, and its entry's type.
constexpr const char* PlanningPicturesLibrary = "libRoboPlanPlanningPictures.so";
using RiskMapPictureFunction = bool (*)(const std::string&, vtkPolyData*, const std::vector<StructureAtRiskSnapshot>&,
                                        const double[3], const std::vector<Vec3>&, const ProposalResult&, std::string&);

/// A sphere's surface (an entry region given only as a sphere), about 1 mm triangles.
vtkSmartPointer<vtkPolyData> SpherePolyData(const double center[3], double radius);

}  // namespace rp
