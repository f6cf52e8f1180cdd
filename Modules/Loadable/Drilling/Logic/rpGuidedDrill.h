#pragma once
// One execution of a planned trajectory with the simulated hand, scored against its plan (issue
// 38): what `roboplan drill --plan`, the Drilling panel and the demo's three executions run.
// The hand (rpSimulatedHand.h) means to drill from the planned entry along the plan at a steady
// speed to a little beyond the target (a hand that relies on a depth stop, or overshoots without
// one), with its tremor and drift; the burr starts at the entry, cutting; the fixtures (none: the
// free hand) act in the drilling servo. The execution is the burr's centre where the burr ran
// (the recorded proxy), scored with rpExecutionScore against the plan, the bone's surface, the
// structures at risk and the bone the burr removed.
#include <memory>
#include <string>
#include <vector>

#include "rpExecutionScore.h"
#include "rpDrillProtection.h"
#include "rpFixtureSet.h"
#include "rpPlanFixtures.h"
#include "rpPlanSnapshot.h"
#include "rpSimulatedHand.h"
#include "vtkRPDrillingLogic.h"

namespace rp {

struct GuidedDrillOptions {
  TrajectoryAxis Plan;
  double PlanDiameterMm = 4;
  double BurrRadiusMm = 2;
  double Rpm = 60000;
  double FeedRate = 2;              // mm/s into hardness-1 bone at the device's maximum force
  double SpeedMmPerS = 2;           // the hand's intended speed along the plan
  double PushBeyondMm = 2;          // how far past the target the hand means to go
  Vec3 IntentOffsetMm;              // the hand means to drill this far off the plan (a registration error)
  bool Hand = true;                 // false: the burr follows the intent exactly (no tremor, no drift, no force)
  HandNoise Noise;
  HandImpedance Grip;
  std::shared_ptr<const FixtureSet> Fixtures;  // nullptr: free hand
  std::vector<ScoredStructure> Structures;     // clearance and enteredForbidden
  // When the run ends: once the hand's intent has ended and the burr has reached the intended end
  // (along the plan, within ArrivalToleranceMm) or stalled (no StallProgressMm deeper for
  // StallSeconds: a depth stop, a protected margin, a bone too hard for the feed), SettleSeconds
  // later; at MaxSeconds of session time at the latest. So a hand faster than the burr cuts waits
  // for the burr, as a surgeon's does.
  double SettleSeconds = 1.5;       // after the intent ended and the burr arrived or stalled
  double StallSeconds = 1.0;
  double StallProgressMm = 0.05;
  double ArrivalToleranceMm = 0.1;
  double MaxSeconds = 120;
  bool Realtime = false;            // the 1 kHz servo thread on the wall clock (default: scripted ticks)
  ServoLoop::Options Loop;
  std::string RecordPath;           // the drill path recording ("" none)
  ProgressCallback Progress;        // share of the hand's stroke and its settling (the panel's bar)
};

struct GuidedDrillResult {
  DrillRunResult Run;
  ExecutionScore Score;
  std::vector<Vec3> Path;           // the burr's centre where the burr ran
  bool EnteredForbidden = false;    // the tool's surface came within a structure's margin
  double DrillSeconds = 0;          // from the start to the last tick that removed bone
  double DepthOvershootMm = 0;      // max(0, the score's depth error)
  std::shared_ptr<const FixtureSet> Fixtures;  // the fixtures it ran with (nullptr: free hand)
};

/// Runs the execution on the logic's bone (built by the caller; drilled by this run) and scores
/// it. False with `error` naming the problem.
bool RunGuidedDrill(vtkRPDrillingLogic* logic, const GuidedDrillOptions& options, GuidedDrillResult& result,
                    std::string& error);

// ---- a plan for the drill (`roboplan drill --plan`, the demo)
/// Loads the plan file into `scene` (a `.mrk.json` trajectory, or a scene with its plan, models and
/// segments) and returns the scene's plan as the Planning logic snapshots it: its trajectories and
/// every structure at risk of the scene (protected models and segments, with their margins). Null
/// with `error` naming the file or the problem.
std::shared_ptr<const PlanSnapshot> LoadPlan(vtkRPScene* scene, const std::string& file, std::string& error);
/// The scene's plan as it is now (after segments were flagged protected, say).
std::shared_ptr<const PlanSnapshot> SnapshotPlan(vtkRPScene* scene, std::string& error);
/// The trajectory to drill: by node ID or name, "" the first. Null with `error` listing them.
const TrajectorySnapshot* ChooseTrajectory(const PlanSnapshot& plan, const std::string& name, std::string& error);
/// The plan's structures at risk as the score measures them, and as the drill bone protects them.
std::vector<ScoredStructure> ScoredStructuresOf(const PlanSnapshot& plan);
std::vector<ProtectedRegion> ProtectedRegionsOf(const PlanSnapshot& plan);

// ---- executing a plan's trajectory (`roboplan drill --plan`, the demo, the guidance benchmark)
/// Drills `trajectory` of `plan` on the logic's bone (built by the caller, not yet drilled) with
/// the fixtures `choice` switches on (its Trajectory is set to this one) and the hand, burr and
/// speeds of `options`: the plan's structures at risk protect the bone (the drill refuses to cut
/// within their margins), are scored, and are the forbidden regions; options' Plan,
/// PlanDiameterMm, Fixtures and Structures come from the plan. False with `error`.
bool DrillPlannedTrajectory(vtkRPDrillingLogic* logic, const PlanSnapshot& plan, const TrajectorySnapshot& trajectory,
                            PlanFixtureChoice choice, GuidedDrillOptions options, GuidedDrillResult& result,
                            std::string& error);

/// The ways one plan is executed and compared under one hand (issue 38): free hand; axis
/// guidance and depth stop; guidance and the structures at risk as forbidden regions.
struct ExecutionWay {
  std::string Name;      // "free hand", ...
  std::string Fixtures;  // as ParseFixtureKinds reads it: "none", "axis,depth", "axis,depth,forbidden"
};
const std::vector<ExecutionWay>& ExecutionWays();

}  // namespace rp
