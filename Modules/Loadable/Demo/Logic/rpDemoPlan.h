#pragma once
// The demo's plan as the drilling stages read it: the Plan stage's trajectory and screw nodes and
// the scene's structures at risk, snapshotted by the Planning logic (one definition of the
// tunnel: the node), and the voxel tibia they are drilled in.
#include <memory>
#include <string>

#include "rpDemoStages.h"
#include "rpDrillBoneBuilder.h"
#include "rpPlanSnapshot.h"

namespace rp {

/// The scene's plan: its trajectories and structures at risk (rpGuidedDrill.h: SnapshotPlan).
/// Null with `why` when the Plan stage made no tunnel or a structure has no surface.
std::shared_ptr<const PlanSnapshot> DemoPlan(const DemoState& state, std::string& why);

/// The voxel tibia between `lo` and `hi` (RAS): this run's tibia segment, cortical / trabecular
/// from the CT, its density following the tibia's display model (the surface the user sees).
/// False with `why` when the run has no tibia segment or model.
bool TibiaDrillSource(const DemoState& state, const Vec3& lo, const Vec3& hi, double voxelMm, DrillBoneSource& source,
                      std::string& why);

}  // namespace rp
