#pragma once
// An execution scored against a trajectory of the scene (issue 38): the one job `roboplan score`
// and the Navigation panel's "Score" run. vtkRPNavigationLogic::PrepareScore takes what the scene
// holds on the main thread (its plan as an immutable PlanSnapshot: the trajectory and the
// structures at risk; the bone's surface copied into world RAS); RunScore then reads the path file
// and scores (rpExecutionScore.h) touching no scene node, so the panel runs it off the GUI thread.
// vtkRPNavigationLogic::ScoreExecution does both at once.
#include <memory>
#include <string>
#include <vector>

#include "rpExecutionPath.h"
#include "rpExecutionScore.h"
#include "rpPlanSnapshot.h"

namespace rp {

struct ScoreRequest {
  std::string Trajectory;            // the scene's trajectory: node ID or name ("" the first)
  std::string PathFile;              // a drilling recording, a PLUS sequence or a CSV R,A,S (rpExecutionPath.h)
  ExecutionPathOptions PathOptions;  // PLUS: the transform to follow and a configuration
  std::string BoneModelNodeID;       // the bone's closed surface, for the breach ("" none)
  double ToolRadiusMm = -1;          // < 0: the recording's burr (a tip: 0)
};

/// What a score read, used and made. Not copyable: Input points into Bone.
struct ScoredExecution {
  ScoreRequest Request;
  std::shared_ptr<const PlanSnapshot> Plan;        // the scene's plan when prepared
  TrajectorySnapshot Trajectory;                   // the chosen one
  std::string BoneName;                            // "" without a bone
  std::shared_ptr<const TriangleMesh> BoneSurface;  // world RAS
  ExecutionPath Path;
  MeshSignedDistance Bone;
  ExecutionInput Input;
  ExecutionScore Score;
  /// What looks wrong though it scores, e.g. a path nowhere near the plan (another frame?).
  std::vector<std::string> Warnings;

  ScoredExecution() = default;
  ScoredExecution(const ScoredExecution&) = delete;
  ScoredExecution& operator=(const ScoredExecution&) = delete;
};

/// A path none of whose points comes this close to the planned segment (entry to target) gets a
/// warning: it is most likely in another frame (a PLUS transform to the tracker, not the patient).
constexpr double FarFromPlanMm = 50;

/// The prepared job's second half, on any thread: reads the path, builds the bone's signed
/// distance, scores. False with `error` naming the file or the problem (a path of one point, a
/// path parallel to the entry plane, a bone that is not closed, ...).
bool RunScore(ScoredExecution& job, std::string& error);

/// The score as `roboplan score --json` prints it: rp::ExecutionScoreJson's keys, `plan` (`file`:
/// `planFile`, the trajectory, its entry, target and tool diameter) and `path` (file, kind,
/// samples, skipped, transform chain, tool radius). The one writer for the command and the panel.
std::string ScoredExecutionJson(const ScoredExecution& job, const std::string& planFile);
/// The same written to `file` (atomically). False with `error` naming the file.
bool WriteScoredExecutionJson(const ScoredExecution& job, const std::string& planFile, const std::string& file,
                              std::string& error);

/// The deviation along depth (0.5 mm bins) as a table (depthMm, deviationMm) and as a chart
/// (Libs/Charts): what `--csv` and `--chart` write and the panel shows.
bool WriteDeviationCsv(const ExecutionScore& score, const std::string& file, std::string& error);
bool WriteDeviationChart(const ExecutionScore& score, const std::string& file, std::string& error, int width = 900,
                         int height = 600);

}  // namespace rp
