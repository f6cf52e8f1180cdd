#include "rpScoreCommand.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpArgParser.h"
#include "rpBenchmarkChart.h"
#include "rpExecutionPath.h"
#include "rpExecutionScoreJson.h"
#include "rpGuidedDrill.h"
#include "rpModelIO.h"
#include "rpPolyDataTriangleMesh.h"
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

struct ScoreRequest {
  std::string Plan, Path, Trajectory, Bone, Chart, Csv;
  ExecutionPathOptions PathOptions;
  double ToolRadius = -1;  // < 0: the recording's (a tip: 0)
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

bool ParseRequest(const ArgParser& parser, ScoreRequest& q, std::ostream& err) {
  q.Plan = parser.Get("plan");
  q.Path = parser.Get("path");
  q.Trajectory = parser.Get("trajectory");
  q.Bone = parser.Get("bone");
  q.Chart = parser.Get("chart");
  q.Csv = parser.Get("csv");
  q.PathOptions.Transform = parser.Get("transform");
  q.PathOptions.Configuration = parser.Get("configuration");
  try {
    if (parser.Has("tool-radius")) q.ToolRadius = parser.GetDouble("tool-radius");
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

// The bone's closed surface for the breach.
bool LoadBone(const std::string& file, MeshSignedDistance& bone, std::string& error) {
  vtkNew<vtkPolyData> polyData;
  TriangleMesh mesh;
  if (!ReadModelFile(file, polyData, error) || !PolyDataToTriangleMesh(polyData, nullptr, mesh, error)) {
    error = "--bone " + file + ": " + error;
    return false;
  }
  if (!bone.Build(mesh, error)) {
    error = "--bone " + file + ": " + error + " (the breach needs a closed surface)";
    return false;
  }
  return true;
}

// What the scoring used and made, for the report.
struct ScoreRun {
  std::shared_ptr<const PlanSnapshot> Plan;
  TrajectorySnapshot Trajectory;
  ExecutionPath Path;
  MeshSignedDistance Bone;
  ExecutionInput Input;
  ExecutionScore Score;
};

int Score(const ScoreRequest& q, ScoreRun& run, std::ostream& err) {
  std::string error;
  vtkNew<vtkRPScene> scene;
  run.Plan = LoadPlan(scene, q.Plan, error);
  const TrajectorySnapshot* t = run.Plan ? ChooseTrajectory(*run.Plan, q.Trajectory, error) : nullptr;
  if (!t) return Fail(err, "--plan " + q.Plan + ": " + error);
  run.Trajectory = *t;
  if (!ReadExecutionPath(q.Path, q.PathOptions, run.Path, error)) return Fail(err, "--path: " + error);
  if (!q.Bone.empty() && !LoadBone(q.Bone, run.Bone, error)) return Fail(err, error);
  ExecutionInput& input = run.Input;
  if (!TrajectoryAxis::Make(t->Entry, t->Target, input.Plan, error)) return Fail(err, "--plan " + q.Plan + ": " + error);
  input.PlanDiameterMm = t->ToolDiameterMm;
  input.ToolRadiusMm = q.ToolRadius >= 0 ? q.ToolRadius : run.Path.ToolRadiusMm;
  input.Path = run.Path.Points;
  input.Bone = q.Bone.empty() ? nullptr : &run.Bone;
  input.Structures = ScoredStructuresOf(*run.Plan);
  if (!ScoreExecution(input, run.Score, error)) return Fail(err, "scoring " + q.Path + ": " + error);
  return 0;
}

// The deviation along depth as a table and a chart, when asked; a figure that cannot be written
// is an error (exit 1) after the scores are printed.
bool WriteFigures(const ScoreRequest& q, const ExecutionScore& score, std::ostream& err) {
  std::vector<double> depth, deviation;
  std::vector<std::vector<double>> rows;
  for (const DeviationSample& d : score.DeviationAlongDepth) {
    depth.push_back(d.DepthMm);
    deviation.push_back(d.DeviationMm);
    rows.push_back({d.DepthMm, d.DeviationMm});
  }
  bool ok = true;
  std::string error;
  if (!q.Csv.empty() && !bench::WriteCSV(q.Csv, {"depthMm", "deviationMm"}, rows, error)) ok = Fail(err, error) == 0;
  if (!q.Chart.empty()) {
    bench::ChartOptions options;
    options.Title = "Deviation from the planned axis along depth";
    options.XLabel = "depth along the plan (mm)";
    options.YLabel = "deviation (mm)";
    if (!bench::WriteChartPNG(q.Chart, {{"deviation", depth, deviation, false}}, options, error)) ok = Fail(err, error) == 0;
  }
  return ok;
}

nlohmann::json ScoreJson(const ScoreRequest& q, const ScoreRun& run) {
  nlohmann::json doc = ExecutionScoreJson(run.Score);
  const TrajectorySnapshot& t = run.Trajectory;
  auto point = [](const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); };
  doc["plan"] = {{"file", q.Plan}, {"trajectory", t.Name}, {"entry", point(t.Entry)}, {"target", point(t.Target)},
                 {"toolDiameterMm", t.ToolDiameterMm}};
  doc["path"] = {{"file", q.Path},         {"kind", run.Path.Kind},       {"samples", run.Path.Samples},
                 {"skipped", run.Path.Skipped}, {"transform", run.Path.Chain}, {"toolRadiusMm", run.Input.ToolRadiusMm}};
  return doc;
}

void ReportText(const ScoreRun& run, std::ostream& out) {
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
  ScoreRequest q;
  if (!ParseRequest(parser, q, err)) return 2;
  ScoreRun run;
  if (const int code = Score(q, run, err)) return code;
  if (parser.Json()) {
    out << ScoreJson(q, run).dump(2) << "\n";
  } else {
    ReportText(run, out);
  }
  return WriteFigures(q, run.Score, err) ? 0 : 1;
}

}  // namespace rp
