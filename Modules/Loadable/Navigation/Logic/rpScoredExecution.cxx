#include "rpScoredExecution.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

#include "rpBenchmarkChart.h"
#include "rpExecutionScoreJson.h"
#include "rpGuidedDrill.h"

namespace rp {

namespace {
// The closest any point of the path comes to the planned segment.
double ClosestToPlanMm(const std::vector<Vec3>& path, const TrajectoryAxis& plan) {
  double closest = std::numeric_limits<double>::infinity();
  for (const Vec3& p : path) {
    const double depth = std::clamp(plan.Depth(p), 0.0, plan.Length());
    closest = std::min(closest, Norm(p - plan.PointAt(depth)));
  }
  return closest;
}
}  // namespace

bool RunScore(ScoredExecution& job, std::string& error) {
  const ScoreRequest& q = job.Request;
  if (!job.Plan) {
    error = "the score was not prepared (no plan)";
    return false;
  }
  if (!ReadExecutionPath(q.PathFile, q.PathOptions, job.Path, error)) return false;
  if (job.BoneSurface && !job.Bone.Build(*job.BoneSurface, error)) {
    error = "the bone '" + job.BoneName + "': " + error + " (the breach needs a closed surface)";
    return false;
  }
  const TrajectorySnapshot& t = job.Trajectory;
  ExecutionInput& input = job.Input;
  input = ExecutionInput{};
  if (!TrajectoryAxis::Make(t.Entry, t.Target, input.Plan, error)) {
    error = "the trajectory '" + t.Name + "': " + error;
    return false;
  }
  input.PlanDiameterMm = t.ToolDiameterMm;
  input.ToolRadiusMm = q.ToolRadiusMm >= 0 ? q.ToolRadiusMm : job.Path.ToolRadiusMm;
  input.Path = job.Path.Points;
  input.Bone = job.BoneSurface ? &job.Bone : nullptr;
  input.Structures = ScoredStructuresOf(*job.Plan);
  if (!ScoreExecution(input, job.Score, error)) {
    error = "scoring " + q.PathFile + ": " + error;
    return false;
  }
  job.Warnings.clear();
  if (const double closest = ClosestToPlanMm(input.Path, input.Plan); closest > FarFromPlanMm) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "the path never comes within %.0f mm of the trajectory '%s' (closest %.1f mm): is it in the plan's "
                  "frame (RAS)? A PLUS transform should end in the patient's frame (e.g. ...ToReference, ...ToRAS)",
                  FarFromPlanMm, t.Name.c_str(), closest);
    job.Warnings.push_back(text);
  }
  return true;
}

std::string ScoredExecutionJson(const ScoredExecution& job, const std::string& planFile) {
  nlohmann::json doc = ExecutionScoreJson(job.Score);
  const TrajectorySnapshot& t = job.Trajectory;
  auto point = [](const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); };
  doc["plan"] = {{"file", planFile}, {"trajectory", t.Name}, {"entry", point(t.Entry)}, {"target", point(t.Target)},
                 {"toolDiameterMm", t.ToolDiameterMm}};
  doc["path"] = {{"file", job.Request.PathFile}, {"kind", job.Path.Kind},        {"samples", job.Path.Samples},
                 {"skipped", job.Path.Skipped},  {"transform", job.Path.Chain}, {"toolRadiusMm", job.Input.ToolRadiusMm}};
  return doc.dump(2);
}

bool WriteScoredExecutionJson(const ScoredExecution& job, const std::string& planFile, const std::string& file,
                              std::string& error) {
  return bench::WriteFigureFile(file, ScoredExecutionJson(job, planFile) + "\n", error);
}

bool WriteDeviationCsv(const ExecutionScore& score, const std::string& file, std::string& error) {
  std::vector<std::vector<double>> rows;
  for (const DeviationSample& d : score.DeviationAlongDepth) rows.push_back({d.DepthMm, d.DeviationMm});
  return bench::WriteCSV(file, {"depthMm", "deviationMm"}, rows, error);
}

bool WriteDeviationChart(const ExecutionScore& score, const std::string& file, std::string& error, int width, int height) {
  std::vector<double> depth, deviation;
  for (const DeviationSample& d : score.DeviationAlongDepth) {
    depth.push_back(d.DepthMm);
    deviation.push_back(d.DeviationMm);
  }
  bench::ChartOptions options;
  options.Title = "Deviation from the planned axis along depth";
  options.XLabel = "depth along the plan (mm)";
  options.YLabel = "deviation (mm)";
  options.Width = width;
  options.Height = height;
  return bench::WriteChartPNG(file, {{"deviation", depth, deviation, false}}, options, error);
}

}  // namespace rp
