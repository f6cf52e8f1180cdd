#pragma once
// The virtual fixtures a plan drives (issue 38), built on the main thread from an immutable plan
// snapshot (rpPlanSnapshot.h, made by the Planning logic from the scene's plan nodes):
//   axis       axis guidance along the chosen trajectory;
//   depth      a depth stop at its target;
//   forbidden  a forbidden region per structure at risk (its closed surface + its safety margin);
//   surface    the seed's constraint mode on a chosen cut plane, or on a model's surface.
// Each fixture's id comes from its node's ID and kind, so a new snapshot (the plan dragged, a
// fixture switched) carries the servo's fades over. The default tunings: DefaultFixtureTuning.
#include <memory>
#include <string>

#include "rpFixtureSet.h"
#include "rpPlanSnapshot.h"

namespace rp {

struct PlanFixtureChoice {
  bool Axis = false, Depth = false, Forbidden = false, Surface = false;
  std::string Trajectory;          // node ID or name; "" the plan's first trajectory
  std::string SurfacePlane;        // the surface constraint on this cut plane (ID or name), or
  std::shared_ptr<const TriangleMesh> SurfaceModel;  // on this model's surface (RAS), when no plane is named
  std::string SurfaceModelNode;    // or on this model node's (ID or name): the Planning logic's
                                   // MakePlanFixtures reads its surface into SurfaceModel (and
                                   // puts the model's name here: it names the fixture)
  FixtureTuning AxisTuning = DefaultFixtureTuning(FixtureKind::AxisGuidance);
  FixtureTuning DepthTuning = DefaultFixtureTuning(FixtureKind::DepthStop);
  FixtureTuning ForbiddenTuning = DefaultFixtureTuning(FixtureKind::ForbiddenRegion);
  FixtureTuning SurfaceTuning = DefaultFixtureTuning(FixtureKind::SurfaceConstraint);
};

/// "axis,depth,forbidden" (any of axis, depth, forbidden, surface; "none" for none) into the
/// choice's switches. False with `error` naming an unknown one.
bool ParseFixtureKinds(const std::string& list, PlanFixtureChoice& choice, std::string& error);

/// The fixture set; nullptr with `error` when a chosen fixture has nothing to act on (no
/// trajectory, a structure at risk without a closed surface, no such plane).
std::shared_ptr<const FixtureSet> BuildPlanFixtures(const PlanSnapshot& plan, const PlanFixtureChoice& choice,
                                                    std::string& error);

}  // namespace rp
