#include "rpTrajectoryProposal.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <unordered_map>

#include "rpMortonCode.h"
#include "rpTrajectoryFigures.h"

namespace rp {
namespace {

// Whether the tool stays in bone once in it: the axis and four lines of its surface, each from
// where it first enters bone to the target, every `step` (each line has its own entry, so an
// oblique entry's footprint is no failure).
bool StaysInBone(const Vec3& entry, const Vec3& target, double radius, double step, const TissueModel& tissue) {
  const Vec3 d = target - entry;
  const Vec3 u = Normalized(d);
  const Vec3 a = std::fabs(u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = Normalized(Cross(u, a)), e2 = Cross(u, e1);
  const Vec3 offsets[5] = {{}, e1 * radius, e1 * -radius, e2 * radius, e2 * -radius};
  const int n = std::max(1, static_cast<int>(std::ceil(Norm(d) / step)));
  for (const Vec3& o : offsets) {
    bool entered = false;
    for (int i = 0; i <= n; ++i) {
      const bool in = tissue.InBone(entry + o + d * (static_cast<double>(i) / n));
      if (entered && !in) return false;
      entered = entered || in;
    }
    if (!entered) return false;
  }
  return true;
}

struct Job {
  const ProposalRequest* Request;
  const std::vector<StructureAtRiskSnapshot>* Structures;
  const TissueModel* Tissue;
  const std::vector<uint32_t>* Order;
  bool TargetOutside;  // the target is outside every structure: a path that does not cross one is outside it
  std::vector<CandidateScore>* Scores;
};

// The target outside every closed structure: then an axis that crosses no surface lies outside.
bool TargetOutsideAll(const Vec3& target, const std::vector<StructureAtRiskSnapshot>& structures) {
  for (const auto& s : structures)
    if (!s.Signed || s.Signed->SignedDistance(target) <= 0) return false;
  return true;
}

void ScoreRange(const Job& job, size_t begin, size_t end) {
  const ProposalRequest& request = *job.Request;
  const auto& structures = *job.Structures;
  std::vector<uint32_t> warm(structures.size(), UINT32_MAX);  // the last closest triangle, per structure
  size_t previous = 0;                                         // the structure nearest the last candidate
  const double radius = 0.5 * request.ToolDiameterMm;
  for (size_t k = begin; k < end; ++k) {
    const uint32_t index = (*job.Order)[k];
    CandidateScore& score = (*job.Scores)[index];
    const Vec3& entry = request.Candidates[index];
    const double length = Norm(request.Target - entry);
    if (!(length > 1e-6)) {
      score.Valid = false;
      continue;
    }
    score.ClearanceMm = score.SlackMm = HUGE_VALF;
    // The structure nearest the last candidate first; each next one only searched as far as it
    // could still be the nearest beyond its margin (the score is the smallest slack).
    const size_t first = previous < structures.size() ? previous : 0;
    for (size_t k = 0; k < structures.size(); ++k) {
      const size_t s = (first + k) % structures.size();
      const StructureAtRiskSnapshot& structure = structures[s];
      const double reach = std::isfinite(score.SlackMm) ? score.SlackMm + structure.SafetyMarginMm + radius : HUGE_VAL;
      SegmentClosestHit hit;
      if (!structure.Tree || reach < 0 ||
          !structure.Tree->ClosestToSegment(entry, request.Target, reach, hit, warm[s] == UINT32_MAX ? nullptr : &warm[s]))
        continue;
      warm[s] = hit.Leaf;
      double clearance = std::sqrt(hit.Distance2) - radius;
      const bool inside = hit.Distance2 > 0 && !job.TargetOutside && structure.Signed &&
                          structure.Signed->SignedDistance(hit.SegmentPoint) < 0;
      if (hit.Distance2 == 0 || inside) clearance = -radius;  // into the structure
      const double slack = clearance - structure.SafetyMarginMm;
      if (slack < score.SlackMm) {
        score.SlackMm = static_cast<float>(slack);
        score.ClearanceMm = static_cast<float>(clearance);
        score.DepthMm = static_cast<float>(hit.T * length);
        score.Structure = static_cast<int16_t>(s);
      }
    }
    if (score.Structure >= 0) previous = static_cast<size_t>(score.Structure);
    if (request.StayInBone && job.Tissue)
      score.InBone = StaysInBone(entry, request.Target, radius, request.BoneStepMm, *job.Tissue);
  }
}

std::vector<int> PickBest(const ProposalRequest& request, const std::vector<CandidateScore>& scores, double separation) {
  std::vector<int> ranked;
  for (size_t i = 0; i < scores.size(); ++i)
    if (scores[i].Valid && scores[i].InBone) ranked.push_back(static_cast<int>(i));
  std::stable_sort(ranked.begin(), ranked.end(), [&](int a, int b) {
    if (scores[a].SlackMm != scores[b].SlackMm) return scores[a].SlackMm > scores[b].SlackMm;
    return Norm2(request.Candidates[a] - request.Target) < Norm2(request.Candidates[b] - request.Target);
  });
  std::vector<int> best;
  for (int i : ranked) {
    if (static_cast<int>(best.size()) >= request.Best) break;
    const bool apart = std::all_of(best.begin(), best.end(), [&](int j) {
      return Norm(request.Candidates[i] - request.Candidates[j]) >= separation;
    });
    if (apart) best.push_back(i);
  }
  return best;
}

}  // namespace

std::vector<uint32_t> SpatialOrder(const std::vector<Vec3>& points) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Vec3& p : points) lo = Min(lo, p), hi = Max(hi, p);
  const double cells = static_cast<double>((1u << 21) - 1);
  std::vector<std::pair<uint64_t, uint32_t>> keys(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double extent = hi[a] - lo[a];
      code |= SpreadMortonBits(static_cast<uint64_t>(extent > 0 ? (points[i][a] - lo[a]) / extent * cells : 0)) << a;
    }
    keys[i] = {code, static_cast<uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> order(points.size());
  for (size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

double MedianSpacing(const std::vector<Vec3>& points) {
  if (points.size() < 2) return 0;
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Vec3& p : points) lo = Min(lo, p), hi = Max(hi, p);
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9});
  const double cell = std::max(extent / std::sqrt(static_cast<double>(points.size())), 1e-9);  // points on a surface
  auto key = [&](int i, int j, int k) { return (static_cast<int64_t>(i) * 73856093) ^ (static_cast<int64_t>(j) * 19349663) ^ (static_cast<int64_t>(k) * 83492791); };
  auto cellOf = [&](const Vec3& p, int c[3]) {
    for (int a = 0; a < 3; ++a) c[a] = static_cast<int>(std::floor((p[a] - lo[a]) / cell));
  };
  std::unordered_map<int64_t, std::vector<uint32_t>> grid;
  for (size_t i = 0; i < points.size(); ++i) {
    int c[3];
    cellOf(points[i], c);
    grid[key(c[0], c[1], c[2])].push_back(static_cast<uint32_t>(i));
  }
  std::vector<double> nearest;
  for (size_t i = 0; i < points.size(); ++i) {
    int c[3];
    cellOf(points[i], c);
    double best = HUGE_VAL;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const auto it = grid.find(key(c[0] + di, c[1] + dj, c[2] + dk));
          if (it == grid.end()) continue;
          for (uint32_t j : it->second)
            if (j != i) best = std::min(best, Norm(points[i] - points[j]));
        }
    if (std::isfinite(best)) nearest.push_back(best);
  }
  if (nearest.empty()) return cell;
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<long>(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2];
}

ProposalResult ProposeTrajectory(const ProposalRequest& request, const std::vector<StructureAtRiskSnapshot>& structures,
                                 const TissueModel* tissue) {
  ProposalResult result;
  if (request.Candidates.empty()) {
    result.Error = "the entry region has no points";
    return result;
  }
  if (request.StayInBone && (!tissue || (!tissue->HasCT() && !tissue->HasLabels()))) {
    result.Error = "staying in bone needs a CT or a segmentation";
    return result;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<uint32_t> ownOrder;
  if (!request.Order || request.Order->size() != request.Candidates.size()) ownOrder = SpatialOrder(request.Candidates);
  const std::vector<uint32_t>& order = ownOrder.empty() ? *request.Order : ownOrder;
  result.Scores.assign(request.Candidates.size(), CandidateScore{});
  const Job job{&request, &structures, tissue, &order, TargetOutsideAll(request.Target, structures), &result.Scores};
  const size_t n = order.size();
  const int threads = std::max(1, std::min<int>(request.Threads, static_cast<int>(n / 64) + 1));
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(ScoreRange, std::cref(job), n * t / threads, n * (t + 1) / threads);
  ScoreRange(job, 0, n / threads);
  for (auto& w : workers) w.join();
  result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.SpacingMm = request.SpacingMm > 0 ? request.SpacingMm : MedianSpacing(request.Candidates);
  const double separation = request.MinimumSeparationMm > 0 ? request.MinimumSeparationMm : 3 * result.SpacingMm;
  result.Best = PickBest(request, result.Scores, separation);
  if (result.Best.empty()) result.Error = request.StayInBone ? "no candidate entry keeps the tool in bone to the target"
                                                             : "no candidate entry is usable";
  return result;
}

}  // namespace rp
