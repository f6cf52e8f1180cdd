#include "rpExecutionScoreJson.h"

#include <cmath>

namespace rp {

namespace {
nlohmann::json Point(const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); }
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json ExecutionScoreJson(const ExecutionScore& s) {
  nlohmann::json doc = {{"entryOffsetMm", s.EntryOffsetMm},
                        {"tipOffsetMm", s.TipOffsetMm},
                        {"angleDeg", s.AngleDeg},
                        {"depthErrorMm", s.DepthErrorMm},
                        {"maxDeviationMm", s.MaxDeviationMm},
                        {"executedEntry", Point(s.ExecutedEntry)},
                        {"executedTip", Point(s.ExecutedTip)},
                        {"executedDirection", Point(s.ExecutedDirection)},
                        {"points", s.Points},
                        {"pathLengthMm", s.PathLengthMm}};
  doc["breach"] = s.HasBreach ? nlohmann::json{{"mm", s.BreachMm}, {"depthMm", s.BreachDepthMm}, {"grade", s.BreachGrade}}
                              : nlohmann::json(nullptr);
  nlohmann::json clearance = nlohmann::json::array();
  for (const StructureClearance& c : s.Clearance)
    clearance.push_back({{"name", c.Name},
                         {"closestMm", Number(c.ClosestMm)},
                         {"depthMm", c.DepthMm},
                         {"marginMm", c.MarginMm},
                         {"withinMargin", c.WithinMargin}});
  doc["clearance"] = clearance;
  doc["outsideVolumeMm3"] = s.HasVolume ? nlohmann::json(s.OutsideVolumeMm3) : nlohmann::json(nullptr);
  doc["drilledVolumeMm3"] = s.HasVolume ? nlohmann::json(s.DrilledVolumeMm3) : nlohmann::json(nullptr);
  nlohmann::json chart = nlohmann::json::array();
  for (const DeviationSample& d : s.DeviationAlongDepth) chart.push_back({{"depthMm", d.DepthMm}, {"deviationMm", d.DeviationMm}});
  doc["deviationAlongDepth"] = chart;
  return doc;
}

}  // namespace rp
