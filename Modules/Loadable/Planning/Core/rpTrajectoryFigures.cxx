#include "rpTrajectoryFigures.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rp {
namespace {

constexpr double Pi = 3.14159265358979323846;

// Two unit vectors perpendicular to the unit `u` and to each other.
void Perpendiculars(const Vec3& u, Vec3& e1, Vec3& e2) {
  const Vec3 a = std::fabs(u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  e1 = Normalized(Cross(u, a));
  e2 = Cross(u, e1);
}

struct Frame {
  Vec3 Start, U, E1, E2;
  double StartDepth = 0;
  Vec3 At(double depth) const { return this->Start + this->U * (depth - this->StartDepth); }
  Vec3 Around(double depth, double radius, double angle) const {
    return this->At(depth) + (this->E1 * std::cos(angle) + this->E2 * std::sin(angle)) * radius;
  }
};

Frame FrameOf(const ToolSpan& tool) {
  Frame f;
  f.Start = tool.Start;
  f.U = tool.Direction();
  f.StartDepth = tool.StartDepthMm;
  Perpendiculars(f.U, f.E1, f.E2);
  return f;
}

// The depth in (lo, hi) where `inside(depth)` changes, by bisection (inside(lo) != inside(hi)).
template <class Inside>
double Bisect(double lo, double hi, Inside&& inside) {
  const bool atLo = inside(lo);
  for (int i = 0; i < 30 && hi - lo > 1e-7; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (inside(mid) == atLo) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Depth intervals where `inside` holds, sampled every `step` and refined by bisection.
template <class Inside>
std::vector<DepthInterval> Intervals(double from, double to, double step, Inside&& inside) {
  std::vector<DepthInterval> out;
  if (!(to > from)) return out;
  const int n = std::max(1, static_cast<int>(std::ceil((to - from) / step)));
  bool previous = inside(from);
  double start = from, last = from;
  for (int i = 1; i <= n; ++i) {
    const double depth = i == n ? to : from + (to - from) * i / n;
    const bool now = inside(depth);
    if (now != previous) {
      const double edge = Bisect(last, depth, inside);
      if (previous) out.push_back({start, edge});
      start = edge;
      previous = now;
    }
    last = depth;
  }
  if (previous) out.push_back({start, to});
  return out;
}

double Total(const std::vector<DepthInterval>& intervals) {
  double sum = 0;
  for (const auto& i : intervals) sum += i.ToMm - i.FromMm;
  return sum;
}

// Per tissue, the intervals where the axis is in it (classified at each step's midpoint).
std::vector<TissueLength> TissuesAlong(const Frame& f, double from, double to, double step, const TissueModel& tissue) {
  const auto& names = tissue.TissueNames();
  std::vector<TissueLength> out(names.size());
  for (size_t i = 0; i < names.size(); ++i) out[i].Name = names[i];
  const int n = std::max(1, static_cast<int>(std::ceil((to - from) / step)));
  for (int i = 0; i < n; ++i) {
    const double a = from + (to - from) * i / n, b = from + (to - from) * (i + 1) / n;
    TissueLength& t = out[static_cast<size_t>(tissue.TissueIndex(f.At(0.5 * (a + b))))];
    if (!t.Intervals.empty() && std::fabs(t.Intervals.back().ToMm - a) < 1e-9) t.Intervals.back().ToMm = b;
    else t.Intervals.push_back({a, b});
    t.LengthMm += b - a;
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](const TissueLength& t) { return t.LengthMm <= 0; }), out.end());
  return out;
}

std::vector<TissueLength> BoneByHU(const Frame& f, const std::vector<DepthInterval>& bone, double step,
                                   const TissueModel& tissue) {
  std::vector<TissueLength> out;
  for (const auto& range : tissue.BoneRanges) out.push_back({range.Tissue, 0, {}});
  for (const auto& interval : bone) {
    const int n = std::max(1, static_cast<int>(std::ceil((interval.ToMm - interval.FromMm) / step)));
    for (int i = 0; i < n; ++i) {
      const double a = interval.FromMm + (interval.ToMm - interval.FromMm) * i / n;
      const double b = interval.FromMm + (interval.ToMm - interval.FromMm) * (i + 1) / n;
      const int range = tissue.BoneRangeOf(tissue.HU(f.At(0.5 * (a + b))));
      if (range < 0) continue;
      TissueLength& t = out[static_cast<size_t>(range)];
      if (!t.Intervals.empty() && std::fabs(t.Intervals.back().ToMm - a) < 1e-9) t.Intervals.back().ToMm = b;
      else t.Intervals.push_back({a, b});
      t.LengthMm += b - a;
    }
  }
  return out;
}

// Points over the tool's cross-section: rings of equal area, evenly spaced around each (so the
// mean of a field that is linear across the tool is its value on the axis).
std::vector<std::pair<double, double>> DiskPoints(double radius, int rings) {
  std::vector<std::pair<double, double>> points;  // (radius, angle)
  for (int k = 0; k < rings; ++k) {
    const int count = 6 * (2 * k + 1);  // proportional to the ring's area
    const double rho = radius * std::sqrt((k + 0.5) / rings);
    for (int m = 0; m < count; ++m) points.push_back({rho, 2 * Pi * (m + 0.5 * (k % 2)) / count});
  }
  return points;
}

std::vector<ProfileSample> Profile(const Frame& f, double from, double to, double radius, const TissueModel& tissue,
                                   const FigureOptions& options) {
  std::vector<ProfileSample> out;
  if (!tissue.HasCT()) return out;
  const auto disk = DiskPoints(radius, options.CrossSectionRings);
  const int n = std::max(1, static_cast<int>(std::round((to - from) / options.ProfileStepMm)));
  for (int i = 0; i <= n; ++i) {
    ProfileSample s;
    s.DepthMm = from + (to - from) * i / n;
    const Vec3 c = f.At(s.DepthMm);
    s.HU = tissue.HU(c);
    s.InBone = tissue.InBone(c);
    s.MinHU = HUGE_VAL, s.MaxHU = -HUGE_VAL;
    double sum = 0;
    for (const auto& [rho, angle] : disk) {
      const double hu = tissue.HU(f.Around(s.DepthMm, rho, angle));
      sum += hu;
      s.MinHU = std::min(s.MinHU, hu), s.MaxHU = std::max(s.MaxHU, hu);
    }
    s.MeanHU = sum / static_cast<double>(disk.size());
    out.push_back(s);
  }
  return out;
}

double CorticalShare(const Frame& f, double from, double to, double radius, double step, const TissueModel& tissue,
                     int angles) {
  if (!tissue.HasCT() || tissue.BoneRanges.empty()) return -1;
  const double corticalMin = tissue.BoneRanges.front().MinHU;
  const int n = std::max(1, static_cast<int>(std::ceil((to - from) / step)));
  long cortical = 0, total = 0;
  for (int i = 0; i < n; ++i) {
    const double depth = from + (to - from) * (i + 0.5) / n;
    for (int a = 0; a < angles; ++a, ++total)
      cortical += tissue.HU(f.Around(depth, radius, 2 * Pi * (a + 0.5) / angles)) >= corticalMin;
  }
  return total ? static_cast<double>(cortical) / total : -1;
}

// Outward normal of the bone's boundary near p (the gradient of the bone indicator, else of the CT).
Vec3 BoneNormal(const Vec3& p, const TissueModel& tissue, double h) {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 d;
    d[a] = h;
    g[a] = tissue.HasLabels() ? tissue.BoneIndicator(p - d) - tissue.BoneIndicator(p + d)
                              : tissue.HU(p - d) - tissue.HU(p + d);
  }
  return Normalized(g);
}

// How far the tool's surface stands beyond the bone at this depth, radially from the axis.
// The axis is in bone: each surface point out of bone is searched back towards the axis.
void RadialBreach(const Frame& f, double depth, double radius, double step, const TissueModel& tissue, int angles,
                  BreachFigure& breach) {
  if (!tissue.InBone(f.At(depth))) return;  // an interval's end, a hair past the boundary
  for (int a = 0; a < angles; ++a) {
    const double angle = 2 * Pi * a / angles;
    if (tissue.InBone(f.Around(depth, radius, angle))) continue;
    const auto out = [&](double rho) { return !tissue.InBone(f.Around(depth, rho, angle)); };
    double rho = 0;
    while (rho + step < radius && !out(rho + step)) rho += step;
    const double boundary = rho + step < radius ? Bisect(rho, rho + step, out) : Bisect(rho, radius, out);
    const double beyond = radius - boundary;
    if (beyond > breach.BreachMm) breach = {true, depth, beyond, 0, f.Around(depth, radius, angle)};
  }
}

// Depth the tool's footprint on an oblique bone surface spans on either side of where the axis
// crosses it (r tan of the angle to the surface normal, at most 3 r): not a breach.
double Footprint(const Frame& f, double depth, double radius, const TissueModel& tissue, double h) {
  const Vec3 n = BoneNormal(f.At(depth), tissue, h);
  const double cosine = std::fabs(Dot(n, f.U));
  if (Norm2(n) == 0 || cosine < 1e-9) return 3 * radius;
  return std::min(3 * radius, radius * std::sqrt(std::max(0.0, 1 - cosine * cosine)) / cosine);
}

// Whether the tool's whole cross-section (its surface, `angles` points) is in bone at this depth.
bool ToolInBone(const Frame& f, double depth, double radius, const TissueModel& tissue, int angles) {
  for (int a = 0; a < angles; ++a)
    if (!tissue.InBone(f.Around(depth, radius, 2 * Pi * a / angles))) return false;
  return true;
}

// How far past the axis' crossing of the bone's surface at `crossing` (going `direction`: +1 into
// the bone, -1 back from an exit) the tool is still entering: its footprint on an oblique surface
// (r tan of the angle to the normal), then until its whole cross-section is in bone (a curved
// surface sags away from the tool by about r²/2R past the crossing), at most 3 r. A tool that never
// gets wholly in within that keeps the footprint alone: standing out of the bone along the way is
// a breach.
double EntryStretch(const Frame& f, double crossing, double direction, double radius, double step,
                    const TissueModel& tissue, int angles, double h) {
  const double cap = 3 * radius;
  const double foot = Footprint(f, crossing, radius, tissue, h);
  for (double s = foot; s < cap; s += 0.25 * step)
    if (ToolInBone(f, crossing + direction * s, radius, tissue, angles)) return s;
  return foot;
}

// Where the axis crosses the bone's surface within 3 r beyond a span's end (`direction` -1 before
// its start, +1 after its end): a plan whose entry or target lies on the surface (as a proposed
// entry does) crosses it there. NaN when the axis stays in bone that far (the span begins or ends
// inside the bone: no crossing to leave out).
double CrossingBeyondSpan(const Frame& f, double end, double direction, double radius, double step,
                          const TissueModel& tissue) {
  const auto inBone = [&](double depth) { return tissue.InBone(f.At(depth)); };
  for (double s = step; s <= 3 * radius + step; s += step) {
    const double depth = end + direction * s;
    if (!inBone(depth)) return Bisect(end + direction * (s - step), depth, inBone);
  }
  return std::nan("");
}

// Where the axis is in bone, the tool's surface out of it: the breach. The stretch where the tool
// is still entering the bone at each crossing of its surface is left out (EntryStretch), also where
// a span's end lies on the surface; so is a stretch where the axis itself is out of bone (a canal,
// or the tool between two bones: the bone intervals show it).
BreachFigure Breach(const Frame& f, const std::vector<DepthInterval>& bone, double radius, double step,
                    const TissueModel& tissue, const FigureOptions& options, double spanFrom, double spanTo) {
  BreachFigure breach;
  const double h = std::max(step, 0.25);
  const int angles = options.SurfaceAngles;
  for (const DepthInterval& interval : bone) {
    double from = interval.FromMm, to = interval.ToMm;
    const double entry = interval.FromMm > spanFrom + 1e-9 ? interval.FromMm
                                                           : CrossingBeyondSpan(f, spanFrom, -1, radius, step, tissue);
    const double exit = interval.ToMm < spanTo - 1e-9 ? interval.ToMm
                                                      : CrossingBeyondSpan(f, spanTo, +1, radius, step, tissue);
    if (!std::isnan(entry)) from = std::max(from, entry + EntryStretch(f, entry, +1, radius, step, tissue, angles, h));
    if (!std::isnan(exit)) to = std::min(to, exit - EntryStretch(f, exit, -1, radius, step, tissue, angles, h));
    if (!(to >= from)) continue;
    const int n = std::max(1, static_cast<int>(std::ceil((to - from) / step)));
    for (int i = 0; i <= n; ++i) RadialBreach(f, from + (to - from) * i / n, radius, step, tissue, angles, breach);
  }
  breach.Grade = GertzbeinRobbinsGrade(breach.BreachMm);
  return breach;
}

}  // namespace

ToolSpan ToolSpanOf(const TrajectorySnapshot& plan) {
  ToolSpan tool;
  tool.End = plan.Target;
  const Vec3 u = plan.Direction();
  if (plan.IsScrew) {
    tool.Start = plan.Target - u * plan.ScrewLengthMm;
    tool.RadiusMm = 0.5 * plan.ScrewDiameterMm;
    tool.StartDepthMm = plan.LengthMm() - plan.ScrewLengthMm;
  } else {
    tool.Start = plan.Entry;
    tool.RadiusMm = 0.5 * plan.ToolDiameterMm;
  }
  return tool;
}

std::vector<DepthInterval> BoneAlongAxis(const ToolSpan& tool, const TissueModel& tissue, double from, double to) {
  const Frame f = FrameOf(tool);
  return Intervals(from, to, tissue.StepMm(), [&](double depth) { return tissue.InBone(f.At(depth)); });
}

ClearanceFigure ToolClearance(const ToolSpan& tool, const StructureAtRiskSnapshot& structure, double step,
                              uint32_t* warmLeaf) {
  ClearanceFigure c;
  c.Name = structure.Name;
  c.SafetyMarginMm = structure.SafetyMarginMm;
  SegmentClosestHit hit;
  if (!structure.Tree || !structure.Tree->ClosestToSegment(tool.Start, tool.End, HUGE_VAL, hit, warmLeaf)) {
    c.ClearanceMm = HUGE_VAL;
    return c;
  }
  if (warmLeaf) *warmLeaf = hit.Leaf;
  const double length = tool.LengthMm();
  c.ToolPoint = hit.SegmentPoint, c.StructurePoint = hit.SurfacePoint;
  c.DepthMm = tool.StartDepthMm + hit.T * length;
  const double distance = std::sqrt(hit.Distance2);
  const bool inside = distance > 0 && structure.Signed && structure.Signed->SignedDistance(hit.SegmentPoint) < 0;
  if (distance > 0 && !inside) {
    c.ClearanceMm = distance - tool.RadiusMm;
  } else {  // the axis enters the structure: how deep, sampled along it
    c.Crosses = true;
    double deepest = 0;
    const int n = std::max(1, static_cast<int>(std::ceil(length / step)));
    for (int i = 0; i <= n && structure.Signed; ++i) {
      const Vec3 p = tool.Start + (tool.End - tool.Start) * (static_cast<double>(i) / n);
      const double sd = structure.Signed->SignedDistance(p);
      if (-sd > deepest) deepest = -sd, c.DepthMm = tool.StartDepthMm + length * i / n, c.ToolPoint = p;
    }
    c.ClearanceMm = -tool.RadiusMm - deepest;
  }
  c.UnderMargin = c.ClearanceMm < c.SafetyMarginMm;
  return c;
}

TrajectoryFigures ComputeTrajectoryFigures(const TrajectorySnapshot& plan, const TissueModel& tissue,
                                           const std::vector<StructureAtRiskSnapshot>& structures,
                                           const FigureOptions& options) {
  TrajectoryFigures out;
  const ToolSpan tool = ToolSpanOf(plan);
  const Frame f = FrameOf(tool);
  const double from = tool.StartDepthMm, to = tool.StartDepthMm + tool.LengthMm(), step = tissue.StepMm();
  out.TrajectoryLengthMm = plan.LengthMm();
  out.LengthMm = tool.LengthMm();
  out.ToolDiameterMm = 2 * tool.RadiusMm;
  if (tissue.HasCT() || tissue.HasLabels()) {
    out.Bone = BoneAlongAxis(tool, tissue, from, to);
    out.LengthInBoneMm = Total(out.Bone);
    out.Tissues = TissuesAlong(f, from, to, step, tissue);
    if (tissue.HasCT()) out.BoneByHU = BoneByHU(f, out.Bone, step, tissue);
    out.Profile = Profile(f, from, to, tool.RadiusMm, tissue, options);
    out.CorticalSurfaceShare = CorticalShare(f, from, to, tool.RadiusMm, step, tissue, options.SurfaceAngles);
    out.Breach = Breach(f, out.Bone, tool.RadiusMm, step, tissue, options, from, to);
  }
  for (const auto& structure : structures) {
    ClearanceFigure c = ToolClearance(tool, structure, step);
    if (plan.IsScrew && plan.HeadLengthMm > 0) {  // the head, beyond the shaft's start
      ToolSpan head;
      head.End = tool.Start;
      head.Start = tool.Start - f.U * plan.HeadLengthMm;
      head.RadiusMm = 0.5 * plan.HeadDiameterMm;
      head.StartDepthMm = tool.StartDepthMm - plan.HeadLengthMm;
      const ClearanceFigure h = ToolClearance(head, structure, step);
      if (h.ClearanceMm < c.ClearanceMm) c = h;
    }
    out.Clearances.push_back(c);
  }
  return out;
}

}  // namespace rp
