#include "rpPlanReport.h"

#include <cmath>

namespace rp {
namespace {

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json IntervalsJson(const std::vector<DepthInterval>& intervals, const char* from, const char* to) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& i : intervals) list.push_back({{from, i.FromMm}, {to, i.ToMm}});
  return list;
}

nlohmann::json TissuesJson(const std::vector<TissueLength>& tissues) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : tissues)
    list.push_back({{"name", t.Name}, {"lengthMm", t.LengthMm}, {"intervals", IntervalsJson(t.Intervals, "fromMm", "toMm")}});
  return list;
}

}  // namespace

nlohmann::json PointJson(const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); }

nlohmann::json TrajectoryJson(const TrajectorySnapshot& plan, const std::string& intendedTissue) {
  nlohmann::json j = {{"name", plan.Name}, {"entry", PointJson(plan.Entry)}, {"target", PointJson(plan.Target)},
                      {"toolDiameterMm", plan.ToolDiameterMm}, {"intendedTissue", intendedTissue}};
  if (plan.IsScrew)
    j["screw"] = {{"diameterMm", plan.ScrewDiameterMm}, {"lengthMm", plan.ScrewLengthMm},
                  {"headDiameterMm", plan.HeadDiameterMm}, {"headLengthMm", plan.HeadLengthMm}};
  return j;
}

nlohmann::json FiguresJson(const TrajectoryFigures& f, const TissueModel& tissue) {
  nlohmann::json j;
  j["lengthMm"] = f.LengthMm;
  j["trajectoryLengthMm"] = f.TrajectoryLengthMm;
  j["toolDiameterMm"] = f.ToolDiameterMm;
  j["lengthInBoneMm"] = f.LengthInBoneMm;
  j["bone"] = IntervalsJson(f.Bone, "entryDepthMm", "exitDepthMm");
  j["tissues"] = TissuesJson(f.Tissues);
  nlohmann::json ranges = nlohmann::json::array(), byDensity = nlohmann::json::array();
  for (size_t i = 0; i < tissue.BoneRanges.size(); ++i) {
    const BoneHURange& r = tissue.BoneRanges[i];
    ranges.push_back({{"tissue", r.Tissue}, {"minHU", r.MinHU}, {"maxHU", Number(r.MaxHU)}});
    if (i < f.BoneByHU.size())
      byDensity.push_back({{"tissue", r.Tissue}, {"lengthMm", f.BoneByHU[i].LengthMm},
                           {"intervals", IntervalsJson(f.BoneByHU[i].Intervals, "fromMm", "toMm")}});
  }
  j["huRanges"] = ranges;
  j["boneByDensity"] = byDensity;
  nlohmann::json profile = nlohmann::json::array();
  for (const auto& s : f.Profile)
    profile.push_back({{"depthMm", s.DepthMm}, {"hu", s.HU}, {"meanHU", s.MeanHU}, {"minHU", s.MinHU},
                       {"maxHU", s.MaxHU}, {"inBone", s.InBone}});
  j["profile"] = profile;
  j["corticalSurfaceShare"] = f.CorticalSurfaceShare < 0 ? nlohmann::json(nullptr) : nlohmann::json(f.CorticalSurfaceShare);
  j["breach"] = f.Breach.Found ? nlohmann::json{{"depthMm", f.Breach.DepthMm}, {"breachMm", f.Breach.BreachMm},
                                                {"grade", f.Breach.Grade}, {"point", PointJson(f.Breach.Point)}}
                               : nlohmann::json(nullptr);
  nlohmann::json clearance = nlohmann::json::array();
  for (const auto& c : f.Clearances)
    clearance.push_back({{"name", c.Name}, {"clearanceMm", Number(c.ClearanceMm)}, {"depthMm", c.DepthMm},
                         {"safetyMarginMm", c.SafetyMarginMm}, {"underMargin", c.UnderMargin},
                         {"entersStructure", c.Crosses}, {"toolPoint", PointJson(c.ToolPoint)},
                         {"structurePoint", PointJson(c.StructurePoint)}});
  j["clearance"] = clearance;
  return j;
}

nlohmann::json ProposalJson(const ProposalRequest& request, const ProposalResult& result,
                            const std::vector<StructureAtRiskSnapshot>& structures) {
  nlohmann::json best = nlohmann::json::array();
  for (int i : result.Best) {
    const CandidateScore& s = result.Scores[static_cast<size_t>(i)];
    const Vec3& entry = request.Candidates[static_cast<size_t>(i)];
    best.push_back({{"entry", PointJson(entry)}, {"clearanceMm", Number(s.ClearanceMm)}, {"slackMm", Number(s.SlackMm)},
                    {"closestStructure", s.Structure >= 0 ? nlohmann::json(structures[static_cast<size_t>(s.Structure)].Name)
                                                          : nlohmann::json(nullptr)},
                    {"closestAtDepthMm", s.DepthMm}, {"lengthMm", Norm(request.Target - entry)}});
  }
  long usable = 0;
  for (const auto& s : result.Scores) usable += s.Valid && s.InBone;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& s : structures) list.push_back({{"name", s.Name}, {"safetyMarginMm", s.SafetyMarginMm}});
  return {{"target", PointJson(request.Target)}, {"toolDiameterMm", request.ToolDiameterMm},
          {"candidates", request.Candidates.size()}, {"usableCandidates", usable},
          {"candidateSpacingMm", result.SpacingMm}, {"stayInBone", request.StayInBone},
          {"structures", list}, {"best", best}, {"seconds", result.Seconds}};
}

nlohmann::json CutJson(const std::vector<vtkRPPlanningLogic::BoneCut>& cuts) {
  nlohmann::json bones = nlohmann::json::array();
  for (const auto& c : cuts)
    bones.push_back({{"name", c.Bone}, {"volumeMm3", c.Figures.VolumeMm3},
                     {"normalSideVolumeMm3", c.Figures.PositiveVolumeMm3},
                     {"otherSideVolumeMm3", c.Figures.NegativeVolumeMm3}, {"cutAreaMm2", c.Figures.CutAreaMm2}});
  return bones;
}

}  // namespace rp
