#include "rpPlanFixtures.h"

#include <sstream>

#include "rpAxisGuidance.h"
#include "rpDepthStop.h"
#include "rpForbiddenRegion.h"
#include "rpSurfaceConstraint.h"

namespace rp {

namespace {
// A stable id from a node's ID and the fixture's kind (FNV-1a).
uint32_t FixtureId(const std::string& node, FixtureKind kind) {
  uint32_t h = 2166136261u;
  for (unsigned char c : node + "/" + FixtureKindName(kind)) h = (h ^ c) * 16777619u;
  return h;
}

bool AddTo(FixtureSet& set, std::shared_ptr<const VirtualFixture> fixture, const FixtureTuning& tuning, std::string& error) {
  return fixture && set.Add(std::move(fixture), tuning, true, error);
}

bool AddTrajectoryFixtures(const PlanSnapshot& plan, const PlanFixtureChoice& c, FixtureSet& set, std::string& error) {
  if (!c.Axis && !c.Depth) return true;
  const TrajectorySnapshot* t = c.Trajectory.empty() ? (plan.Trajectories.empty() ? nullptr : &plan.Trajectories.front())
                                                     : plan.FindTrajectory(c.Trajectory);
  if (!t) {
    error = c.Trajectory.empty() ? "the plan has no trajectory for axis guidance or a depth stop"
                                 : "the plan has no trajectory '" + c.Trajectory + "'";
    return false;
  }
  TrajectoryAxis axis;
  if (!TrajectoryAxis::Make(t->Entry, t->Target, axis, error)) {
    error = "trajectory '" + t->Name + "': " + error;
    return false;
  }
  if (c.Axis && !AddTo(set, std::make_shared<AxisGuidance>(FixtureId(t->NodeID, FixtureKind::AxisGuidance), t->Name, axis),
                       c.AxisTuning, error))
    return false;
  return !c.Depth || AddTo(set, std::make_shared<DepthStop>(FixtureId(t->NodeID, FixtureKind::DepthStop), t->Name, axis),
                           c.DepthTuning, error);
}

bool AddForbiddenRegions(const PlanSnapshot& plan, const PlanFixtureChoice& c, FixtureSet& set, std::string& error) {
  if (!c.Forbidden) return true;
  if (plan.StructuresAtRisk.empty()) {
    error = "the plan has no structure at risk for a forbidden region";
    return false;
  }
  for (const StructureAtRiskSnapshot& s : plan.StructuresAtRisk) {
    if (!s.Signed) {
      error = "structure at risk '" + s.Name + "' is not a closed surface: a forbidden region needs its inside";
      return false;
    }
    const std::string node = s.NodeID + (s.SegmentID.empty() ? "" : "/" + s.SegmentID);
    auto region = ForbiddenRegion::Make(FixtureId(node, FixtureKind::ForbiddenRegion), s.Name, s.Signed, s.SafetyMarginMm, error);
    if (!region || !set.Add(std::move(region), c.ForbiddenTuning, true, error)) return false;
  }
  return true;
}

bool AddSurfaceConstraint(const PlanSnapshot& plan, const PlanFixtureChoice& c, FixtureSet& set, std::string& error) {
  if (!c.Surface) return true;
  if (!c.SurfaceModelNode.empty() && !c.SurfaceModel) {
    error = "the surface constraint's model '" + c.SurfaceModelNode + "' was not read (vtkRPPlanningLogic::MakePlanFixtures reads it)";
    return false;
  }
  if (!c.SurfacePlane.empty() || !c.SurfaceModel) {
    const CutPlaneSnapshot* p = c.SurfacePlane.empty() ? (plan.Planes.empty() ? nullptr : &plan.Planes.front())
                                                       : plan.FindPlane(c.SurfacePlane);
    if (!p) {
      error = c.SurfacePlane.empty() ? "the surface constraint needs a cut plane in the plan or a model"
                                     : "the plan has no cut plane '" + c.SurfacePlane + "'";
      return false;
    }
    return AddTo(set, SurfaceConstraint::Plane(FixtureId(p->NodeID, FixtureKind::SurfaceConstraint), p->Name, p->Origin, p->Normal),
                 c.SurfaceTuning, error);
  }
  const std::string name = c.SurfaceModelNode.empty() ? "model" : c.SurfaceModelNode;
  auto surface = SurfaceConstraint::Mesh(FixtureId(name, FixtureKind::SurfaceConstraint), name, *c.SurfaceModel, error);
  return surface && set.Add(std::move(surface), c.SurfaceTuning, true, error);
}
}  // namespace

bool ParseFixtureKinds(const std::string& list, PlanFixtureChoice& choice, std::string& error) {
  choice.Axis = choice.Depth = choice.Forbidden = choice.Surface = false;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item == "axis") choice.Axis = true;
    else if (item == "depth") choice.Depth = true;
    else if (item == "forbidden") choice.Forbidden = true;
    else if (item == "surface") choice.Surface = true;
    else if (item == "none" || item.empty()) continue;
    else {
      error = "unknown fixture '" + item + "' (known: axis, depth, forbidden, surface, none)";
      return false;
    }
  }
  return true;
}

std::shared_ptr<const FixtureSet> BuildPlanFixtures(const PlanSnapshot& plan, const PlanFixtureChoice& choice,
                                                    std::string& error) {
  auto set = std::make_shared<FixtureSet>();
  if (!AddTrajectoryFixtures(plan, choice, *set, error) || !AddForbiddenRegions(plan, choice, *set, error) ||
      !AddSurfaceConstraint(plan, choice, *set, error))
    return nullptr;
  return set;
}

}  // namespace rp
