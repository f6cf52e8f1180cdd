#include "rpScoreCommand.h"

#include <cstdio>
#include <stdexcept>

#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpArgParser.h"
#include "rpDataLoader.h"
#include "rpModelIO.h"
#include "rpScoredExecution.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"

namespace rp {

namespace {

const char* const Summary =
    "An execution scored against its plan: the tool path (a drilling recording from `roboplan drill "
    "--record`, a PLUS tracked-frame sequence (.igs.mha, .igs.nrrd) followed through --transform, or a CSV "
    "with the header R,A,S: one tool-tip point per row, mm, RAS, in the order drilled) against the plan's "
    "trajectory (a Slicer .mrk.json line, or a scene with its plan and structures at risk). Prints the entry "
    "and tip offsets (where the executed axis, a line fitted to the path, crosses the planes through the "
    "planned entry and target normal to the plan), the angle between the axes, the depth error (deepest "
    "point along the plan minus the target's depth), the largest deviation from the planned axis, the "
    "breach of the tool out of --bone (with its Gertzbein-Robbins grade), the closest approach to each "
    "structure at risk of the plan, and the volume the tool swept outside the plan's cylinder (with a tool "
    "radius: the recording's burr, or --tool-radius).";

// The command's arguments: the plan and bone files, the figures, and the logic's request.
struct ScoreArguments {
  std::string Plan, Bone, Chart, Csv;
  ScoreRequest Request;
};

void DeclareOptions(ArgParser& parser) {
  parser.Option("plan", "FILE", "the plan: a .mrk.json trajectory (Slicer markups line) or a scene with its plan")
      .Required()
      .Option("path", "FILE", "the executed path: a drilling recording, a PLUS sequence (.igs.mha, .igs.nrrd) or a CSV R,A,S")
      .Required()
      .Option("transform", "NAME", "PLUS sequences: the transform to follow to the plan's frame, e.g. StylusTipToReference")
      .Option("configuration", "FILE", "PLUS sequences: a PLUS configuration whose CoordinateDefinitions add fixed transforms")
      .Option("trajectory", "NAME", "which trajectory of the plan (node ID or name; default the first)")
      .Option("tool-radius", "MM", "the tool's radius (default: a drilling recording's burr, else 0: a tip)")
      .Number()
      .AtLeast(0)
      .AtMost(10)
      .Option("bone", "FILE", "the bone's closed surface model, for the breach (" + ModelFileExtensionsText() + ")")
      .Option("chart", "FILE.png", "write the deviation along depth as a chart")
      .Option("csv", "FILE.csv", "write the deviation along depth as a table (depthMm, deviationMm)");
}

bool ParseRequest(const ArgParser& parser, ScoreArguments& q, std::ostream& err) {
  q.Plan = parser.Get("plan");
  q.Bone = parser.Get("bone");
  q.Chart = parser.Get("chart");
  q.Csv = parser.Get("csv");
  q.Request.PathFile = parser.Get("path");
  q.Request.Trajectory = parser.Get("trajectory");
  q.Request.PathOptions.Transform = parser.Get("transform");
  q.Request.PathOptions.Configuration = parser.Get("configuration");
  try {
    if (parser.Has("tool-radius")) q.Request.ToolRadiusMm = parser.GetDouble("tool-radius");
  } catch (const std::invalid_argument& e) {
    err << "roboplan score: " << e.what() << "\n";
    return false;
  }
  return true;
}

int Fail(std::ostream& err, const std::string& message) {
  err << "roboplan score: " << message << "\n";
  return 1;
}

// Parse -> the Navigation logic -> report: the plan file (and the bone) loaded into a scene of
// its own, scored by vtkRPNavigationLogic as the panel scores the viewer's scene.
int Score(const ScoreArguments& q, ScoredExecution& run, std::ostream& err) {
  vtkNew<vtkRPScene> scene;
  const LoadResult plan = LoadPath(scene, q.Plan);
  if (!plan.Ok) return Fail(err, "--plan " + q.Plan + ": " + plan.Error);
  ScoreRequest request = q.Request;
  if (!q.Bone.empty()) {
    vtkNew<vtkPolyData> polyData;
    std::string error;
    if (!ReadModelFile(q.Bone, polyData, error)) return Fail(err, "--bone " + q.Bone + ": " + error);
    vtkNew<vtkRPModelNode> bone;
    bone->SetName(q.Bone);
    bone->SetPolyData(polyData);
    scene->AddNode(bone);
    request.BoneModelNodeID = bone->GetID();
  }
  vtkNew<vtkRPNavigationLogic> logic;
  logic->SetScene(scene);
  std::string error;
  if (!logic->PrepareScore(request, run, error)) return Fail(err, "--plan " + q.Plan + ": " + error);
  if (!RunScore(run, error)) return Fail(err, error);
  for (const std::string& warning : run.Warnings) err << "roboplan score: warning: " << warning << "\n";
  return 0;
}

// The deviation along depth as a table and a chart, when asked; a figure that cannot be written
// is an error (exit 1) after the scores are printed.
bool WriteFigures(const ScoreArguments& q, const ExecutionScore& score, std::ostream& err) {
  bool ok = true;
  std::string error;
  if (!q.Csv.empty() && !WriteDeviationCsv(score, q.Csv, error)) ok = Fail(err, error) == 0;
  if (!q.Chart.empty() && !WriteDeviationChart(score, q.Chart, error)) ok = Fail(err, error) == 0;
  return ok;
}

void ReportText(const ScoredExecution& run, std::ostream& out) {
  const ExecutionScore& s = run.Score;
  char line[256];
  std::snprintf(line, sizeof line, "%s (%zu points of %zu) against '%s':\n", run.Path.Kind.c_str(), run.Path.Points.size(),
                run.Path.Samples, run.Trajectory.Name.c_str());
  out << line;
  std::snprintf(line, sizeof line, "  entry offset %.3f mm, tip offset %.3f mm, angle %.3f deg\n", s.EntryOffsetMm,
                s.TipOffsetMm, s.AngleDeg);
  out << line;
  std::snprintf(line, sizeof line, "  depth error %+.3f mm, largest deviation %.3f mm\n", s.DepthErrorMm, s.MaxDeviationMm);
  out << line;
  if (s.HasBreach) {
    std::snprintf(line, sizeof line, "  breach %.2f mm (Gertzbein-Robbins grade %d)\n", s.BreachMm, s.BreachGrade);
    out << line;
  }
  for (const StructureClearance& c : s.Clearance) {
    std::snprintf(line, sizeof line, "  closest to %s: %.2f mm (margin %.2f mm)%s\n", c.Name.c_str(), c.ClosestMm,
                  c.MarginMm, c.WithinMargin ? " WITHIN THE MARGIN" : "");
    out << line;
  }
  if (s.HasVolume) {
    std::snprintf(line, sizeof line, "  swept %.1f mm3, of which %.1f mm3 outside the plan's cylinder\n", s.DrilledVolumeMm3,
                  s.OutsideVolumeMm3);
    out << line;
  }
}

}  // namespace

int RunScoreCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("score", Summary);
  DeclareOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  ScoreArguments q;
  if (!ParseRequest(parser, q, err)) return 2;
  ScoredExecution run;
  if (const int code = Score(q, run, err)) return code;
  if (parser.Json()) {
    out << ScoredExecutionJson(run, q.Plan) << "\n";
  } else {
    ReportText(run, out);
  }
  return WriteFigures(q, run.Score, err) ? 0 : 1;
}

}  // namespace rp
