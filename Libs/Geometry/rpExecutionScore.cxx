#include "rpExecutionScore.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace rp {

namespace {

constexpr double FitSpacingMm = 0.1;       // the executed axis is fitted to the path every 0.1 mm
constexpr double BoneStepMm = 0.05;        // where the plan enters and leaves the bone
constexpr double MaxSweepVoxels = 4e7;     // the swept tool's grid is coarsened beyond this

double SegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double ab2 = Norm2(ab);
  const double t = ab2 > 0 ? std::clamp(Dot(p - a, ab) / ab2, 0.0, 1.0) : 0.0;
  return Norm(p - (a + ab * t));
}

// Where the plan's axis runs inside the bone: from the first depth in bone to the first depth out
// of it again (or the target). False when the planned segment never enters the bone.
bool PlannedSpanInBone(const TrajectoryAxis& plan, const MeshSignedDistance& bone, double& in, double& out) {
  const int steps = std::max(1, static_cast<int>(std::ceil(plan.Length() / BoneStepMm)));
  bool inside = false;
  for (int i = 0; i <= steps; ++i) {
    const double depth = plan.Length() * i / steps;
    const bool now = bone.SignedDistance(plan.PointAt(depth)) < 0;
    if (now && !inside) {  // the first stretch of bone is scored
      in = depth;
      inside = true;
    } else if (!now && inside) {
      out = depth;
      return true;
    }
  }
  if (!inside) return false;
  out = plan.Length();
  return true;
}

void ScoreBreach(const ExecutionInput& input, double radius, ExecutionScore& score) {
  score.HasBreach = true;
  double in = 0, out = 0;
  if (!PlannedSpanInBone(input.Plan, *input.Bone, in, out)) return;
  for (const Vec3& p : input.Path) {
    const double depth = input.Plan.Depth(p);
    if (depth < in + radius || depth > out - radius) continue;
    const double breach = input.Bone->SignedDistance(p) + radius;  // the tool's surface beyond the bone's
    if (breach > score.BreachMm) {
      score.BreachMm = breach;
      score.BreachDepthMm = depth;
    }
  }
  score.BreachGrade = GertzbeinRobbinsGrade(score.BreachMm);
}

void ScoreClearance(const ExecutionInput& input, const std::vector<Vec3>& path, double radius, ExecutionScore& score) {
  for (const ScoredStructure& s : input.Structures) {
    StructureClearance c;
    c.Name = s.Name;
    c.MarginMm = s.MarginMm;
    c.ClosestMm = HUGE_VAL;
    if (s.Surface && !s.Surface->Empty())
      for (const Vec3& p : path) {
        const double d = s.Surface->SignedDistance(p) - radius;
        if (d < c.ClosestMm) {
          c.ClosestMm = d;
          c.DepthMm = input.Plan.Depth(p);
        }
      }
    c.WithinMargin = c.ClosestMm < c.MarginMm;
    score.Clearance.push_back(c);
  }
}

bool OutsidePlan(const ExecutionInput& input, const Vec3& p) {
  const double depth = input.Plan.Depth(p);
  return depth < 0 || depth > input.Plan.Length() || input.Plan.Distance(p) > 0.5 * input.PlanDiameterMm;
}

// The swept tool (spheres of `radius` along the path) voxelized; the bone's inside only, when given.
void SweptVolume(const ExecutionInput& input, const std::vector<Vec3>& path, double radius, ExecutionScore& score) {
  Vec3 lo = path.front(), hi = path.front();
  for (const Vec3& p : path) {
    lo = Min(lo, p);
    hi = Max(hi, p);
  }
  const Vec3 pad{radius, radius, radius};
  lo = lo - pad;
  hi = hi + pad;
  const Vec3 size = hi - lo;
  double h = input.SweepVoxelMm > 0 ? input.SweepVoxelMm : 0.1;
  while (size.x * size.y * size.z / (h * h * h) > MaxSweepVoxels) h *= 1.25;
  const int n[3] = {std::max(1, int(std::ceil(size.x / h))), std::max(1, int(std::ceil(size.y / h))),
                    std::max(1, int(std::ceil(size.z / h)))};
  std::vector<uint8_t> swept(size_t(n[0]) * n[1] * n[2], 0);
  auto index = [&](double v, double origin, int count) { return std::clamp(int(std::floor((v - origin) / h)), 0, count - 1); };
  for (size_t s = 0; s + 1 < path.size() || s == 0; ++s) {
    const Vec3 a = path[s], b = path[std::min(s + 1, path.size() - 1)];
    const Vec3 blo = Min(a, b) - pad, bhi = Max(a, b) + pad;
    for (int k = index(blo.z, lo.z, n[2]); k <= index(bhi.z, lo.z, n[2]); ++k)
      for (int j = index(blo.y, lo.y, n[1]); j <= index(bhi.y, lo.y, n[1]); ++j)
        for (int i = index(blo.x, lo.x, n[0]); i <= index(bhi.x, lo.x, n[0]); ++i) {
          uint8_t& cell = swept[(size_t(k) * n[1] + j) * n[0] + i];
          if (cell) continue;
          const Vec3 c = lo + Vec3{(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
          if (SegmentDistance(c, a, b) <= radius) cell = 1;
        }
    if (path.size() == 1) break;
  }
  const double voxel = h * h * h;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (!swept[(size_t(k) * n[1] + j) * n[0] + i]) continue;
        const Vec3 c = lo + Vec3{(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
        if (input.Bone && input.Bone->SignedDistance(c) >= 0) continue;
        score.DrilledVolumeMm3 += voxel;
        if (OutsidePlan(input, c)) score.OutsideVolumeMm3 += voxel;
      }
  score.HasVolume = true;
}

void ScoreVolume(const ExecutionInput& input, const std::vector<Vec3>& path, double radius, ExecutionScore& score) {
  if (!input.Removed.empty()) {
    for (const RemovedVoxel& v : input.Removed) {
      score.DrilledVolumeMm3 += v.VolumeMm3;
      if (OutsidePlan(input, v.Center)) score.OutsideVolumeMm3 += v.VolumeMm3;
    }
    score.HasVolume = true;
  } else if (input.ToolRadiusMm > 0) {
    SweptVolume(input, path, radius, score);
  }
}

// Deviation: the distance from the planned axis, from the entry plane on (the approach to the
// entry is not scored); the chart bins it by depth.
void ScoreDeviation(const ExecutionInput& input, ExecutionScore& score) {
  const double bin = input.DeviationBinMm > 0 ? input.DeviationBinMm : 0.5;
  std::map<long, double> farthest;
  for (const Vec3& p : input.Path) {
    const double depth = input.Plan.Depth(p);
    if (depth < 0) continue;
    const double d = input.Plan.Distance(p);
    score.MaxDeviationMm = std::max(score.MaxDeviationMm, d);
    double& inBin = farthest.emplace(static_cast<long>(std::floor(depth / bin)), 0.0).first->second;
    inBin = std::max(inBin, d);
  }
  for (const auto& [b, d] : farthest) score.DeviationAlongDepth.push_back({(b + 0.5) * bin, d});
}

}  // namespace

int GertzbeinRobbinsGrade(double breachMm) noexcept {
  if (!(breachMm > 0)) return 0;
  if (breachMm < 2) return 1;
  if (breachMm < 4) return 2;
  if (breachMm <= 6) return 3;
  return 4;
}

std::vector<Vec3> ResampleByLength(const std::vector<Vec3>& path, double spacing) {
  std::vector<Vec3> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  double carried = 0;  // length since the last sample
  for (size_t i = 1; i < path.size(); ++i) {
    const Vec3 a = path[i - 1], b = path[i];
    const double length = Norm(b - a);
    double at = spacing - carried;
    while (at <= length) {
      out.push_back(a + (b - a) * (at / length));
      at += spacing;
    }
    carried = length - (at - spacing);
  }
  if (Norm(out.back() - path.back()) > 1e-12) out.push_back(path.back());
  return out;
}

bool ScoreExecution(const ExecutionInput& input, ExecutionScore& score, std::string& error) {
  score = ExecutionScore{};
  score.Points = input.Path.size();
  for (size_t i = 0; i < input.Path.size(); ++i)
    if (!Finite(input.Path[i])) {
      error = "the path's point " + std::to_string(i + 1) + " is not a finite point";
      return false;
    }
  for (size_t i = 1; i < input.Path.size(); ++i) score.PathLengthMm += Norm(input.Path[i] - input.Path[i - 1]);
  if (input.Path.size() < 2 || !(score.PathLengthMm > 1e-6)) {
    error = "the path has fewer than two distinct points: no axis to score";
    return false;
  }
  if (!(input.Plan.Length() > 0)) {
    error = "the plan has no trajectory (entry and target)";
    return false;
  }
  const std::vector<Vec3> path = ResampleByLength(input.Path, FitSpacingMm);
  Vec3 centroid, direction;
  if (!FitLine(path.data(), path.size(), centroid, direction)) {
    error = "no line fits the path (all its points coincide)";
    return false;
  }
  const TrajectoryAxis& plan = input.Plan;
  if (!LinePlaneIntersection(centroid, direction, plan.Entry(), plan.Direction(), score.ExecutedEntry) ||
      !LinePlaneIntersection(centroid, direction, plan.Target(), plan.Direction(), score.ExecutedTip)) {
    error = "the executed axis runs parallel to the plan's entry plane: it never crosses the planned axis's depth";
    return false;
  }
  score.ExecutedDirection = direction;
  score.EntryOffsetMm = Norm(score.ExecutedEntry - plan.Entry());
  score.TipOffsetMm = Norm(score.ExecutedTip - plan.Target());
  score.AngleDeg = AngleBetweenDegrees(direction, plan.Direction());
  double deepest = -HUGE_VAL;
  for (const Vec3& p : input.Path) deepest = std::max(deepest, plan.Depth(p));
  score.DepthErrorMm = deepest - plan.Length();
  ScoreDeviation(input, score);
  const double radius = input.ToolRadiusMm > 0 ? input.ToolRadiusMm : 0.5 * input.PlanDiameterMm;
  if (input.Bone && !input.Bone->Empty()) ScoreBreach(input, radius, score);
  ScoreClearance(input, path, radius, score);
  ScoreVolume(input, ResampleByLength(input.Path, std::min(FitSpacingMm, 0.5 * input.SweepVoxelMm)), radius, score);
  return true;
}

}  // namespace rp
