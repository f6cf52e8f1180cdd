#pragma once
// A plan's pictures for the report, the CLI and the panel: the HU profile chart (CT numbers against
// depth along the axis and over the tool's cross-section, with the bone ranges of materials.json
// marked) and the risk map (the entry region coloured by clearance, with the structures at risk,
// the target and the best trajectories). PNGs drawn offscreen (Libs/Charts).
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"

class vtkPolyData;

namespace rp {

bool WriteProfileChart(const std::string& path, const TrajectoryFigures& figures, const TissueModel& tissue,
                       const std::string& planName, std::string& error);

/// `riskMap` carries the point scalar "clearanceMm" (vtkRPPlanningLogic::RiskMapPolyData).
bool WriteRiskMapPicture(const std::string& path, vtkPolyData* riskMap, const std::vector<StructureAtRiskSnapshot>& structures,
                         const double target[3], const std::vector<Vec3>& candidates, const ProposalResult& result,
                         std::string& error);

/// A sphere's surface (an entry region given only as a sphere), about 1 mm triangles.
vtkSmartPointer<vtkPolyData> SpherePolyData(const double center[3], double radius);

}  // namespace rp
