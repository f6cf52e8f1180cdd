#include "rpBurrProxy.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace rp {

namespace {
inline Vec3 Splat(double s) { return {s, s, s}; }
}  // namespace

void BurrProxy::Reset(const Vec3& position) noexcept {
  ShellDirections();  // build the shell now, not in a tick
  this->P = position;
  this->State = BurrContact{};
  this->State.Anchor = position;
}

namespace {
// Gap (mm) between the burr's surface and the bone along a shell direction, from the density ρ
// sampled at the burr's surface point (½ is the bone's surface, the ramp is two voxels wide),
// less the allowance: the skin, and the trilinear interpolation's error on the sphere the burr
// carved (its ramp is convex in the voxel position: interpolation overestimates it by about
// h²/4r), so the burr's own walls never block it.
inline double Gap(double rho, double spacing, double allowance) noexcept { return (0.5 - rho) * 2.0 * spacing + allowance; }
inline double Allowance(double spacing, double radius) noexcept {
  return BurrProxy::Skin * spacing + 1.5 * spacing * spacing / (4.0 * radius);
}

struct Shell {
  Vec3 Directions[BurrProxy::ShellPoints];
  Shell() {
    // Fibonacci lattice: even spacing, no pole clusters.
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < BurrProxy::ShellPoints; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / BurrProxy::ShellPoints;
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      this->Directions[i] = {r * std::cos(golden * i), r * std::sin(golden * i), z};
    }
  }
};
const Shell& TheShell() noexcept {
  static const Shell shell;  // built on first use (no allocation)
  return shell;
}
}  // namespace

const Vec3* BurrProxy::ShellDirections() noexcept { return TheShell().Directions; }

double BurrProxy::Sweep(const DrillVolume& volume, const Vec3& from, const Vec3& to, double radius,
                        double& startOverlap, const double* atFrom) noexcept {
  const double h = volume.Spacing();
  const Vec3 d = to - from;
  const double length = Norm(d);
  startOverlap = 0;
  if (!(length > 0)) return 2.0;
  const Vec3 dir = d / length;
  const Vec3* u = ShellDirections();
  const double allowance = Allowance(h, radius);
  auto startDensity = [&](int i) { return atFrom ? atFrom[i] : volume.Sample(from + u[i] * radius); };
  // The points facing the move; those already in the bone at the start block a move that heads
  // into them (within 60°) and are ignored otherwise (the burr slides past them). The point
  // facing the move most squarely first: pressing on the bone it is in it, and one sample decides.
  int front = 0;
  for (int i = 1; i < ShellPoints; ++i)
    if (Dot(u[i], dir) > Dot(u[front], dir)) front = i;
  if (const double gap = Gap(startDensity(front), h, allowance); gap <= 0) {
    startOverlap = -gap;
    return 0.0;
  }
  int ahead[ShellPoints];
  int n = 0;
  double gapBefore = HUGE_VAL;
  for (int i = 0; i < ShellPoints; ++i) {
    const double c = Dot(u[i], dir);
    if (c <= 0) continue;
    const double gap = Gap(startDensity(i), h, allowance);
    if (gap <= 0) {
      startOverlap = std::max(startOverlap, -gap);
      if (c > 0.5) return 0.0;
      continue;
    }
    gapBefore = std::min(gapBefore, gap);
    ahead[n++] = i;
  }
  // Half a voxel at a time (no pop-through: the ramp is two voxels wide), first crossing wins.
  const int steps = std::max(1, static_cast<int>(std::ceil(length / (0.5 * h))));
  const Vec3 step = d / steps;
  for (int s = 1; s <= steps; ++s) {
    const Vec3 p = from + step * s;
    double gap = HUGE_VAL;
    for (int a = 0; a < n; ++a) gap = std::min(gap, Gap(volume.Sample(p + u[ahead[a]] * radius), h, allowance));
    if (gap <= 0) {
      // The smallest gap falls about linearly along the step: interpolate, a hair short of it.
      const double f = gapBefore < HUGE_VAL ? gapBefore / (gapBefore - gap) : 0.0;
      return std::max(0.0, (s - 1 + std::clamp(f, 0.0, 1.0)) / steps - 1e-3 * h / length);
    }
    gapBefore = gap;
  }
  return 2.0;
}

bool BurrProxy::Touching(const DrillVolume& volume, const Vec3& p, double radius, const Vec3& push,
                         BurrContact& contact, double* shell) noexcept {
  const double h = volume.Spacing();
  const double band = TouchBand * h;
  const auto& materials = volume.Materials();
  const Vec3 pushDir = Normalized(push);
  const bool anyDirection = Norm2(pushDir) == 0;
  const Vec3* u = ShellDirections();
  const double allowance = Allowance(h, radius);
  Vec3 sum{};
  int count = 0;
  double stiffAhead = -1, stiffAny = -1;
  uint8_t stiffAheadMaterial = 0, stiffAnyMaterial = 0;
  double aheadWeight[DrillVolume::MaxMaterials + 1] = {};  // contact weight ahead, per material
  for (int i = 0; i < ShellPoints; ++i) {
    uint8_t code;
    const double rho = volume.Sample(p + u[i] * radius, code);
    if (shell) shell[i] = rho;
    if (rho <= 0) continue;
    const double gap = Gap(rho, h, allowance);
    if (gap >= band) continue;
    ++count;
    const double weight = std::min(band - gap, 2 * band);
    sum -= u[i] * weight;  // inward normal (bone → burr centre)
    const uint8_t m = code & DrillVolume::MaterialMask;
    if (m == 0 || size_t(m) > materials.size()) continue;
    const Material& material = materials[m - 1];
    if (material.Stiffness > stiffAny) stiffAny = material.Stiffness, stiffAnyMaterial = m;
    const double ahead = anyDirection ? 1.0 : Dot(u[i], pushDir);
    if (ahead > 0) {  // the point is ahead of the push
      if (material.Stiffness > stiffAhead) stiffAhead = material.Stiffness, stiffAheadMaterial = m;
      aheadWeight[m] += weight * ahead;
    }
  }
  contact.Voxels = count;
  contact.InContact = count > 0;
  if (count == 0) return false;
  const double n = Norm(sum);
  contact.Normal = n > 1e-9 ? sum / n : Vec3{};
  contact.Material = stiffAheadMaterial ? stiffAheadMaterial : stiffAnyMaterial;
  contact.CutMaterial = 0;
  contact.CutHardness = 0;
  double total = 0, hardness = 0;
  for (size_t m = 1; m <= materials.size() && m <= size_t(DrillVolume::MaxMaterials); ++m) {
    total += aheadWeight[m];
    hardness += aheadWeight[m] * materials[m - 1].Hardness;
    if (aheadWeight[m] > 0 && (contact.CutMaterial == 0 || aheadWeight[m] > aheadWeight[contact.CutMaterial]))
      contact.CutMaterial = static_cast<uint8_t>(m);
  }
  if (total > 0) contact.CutHardness = hardness / total;
  return true;
}

bool BurrProxy::SurfaceDistance(const DrillVolume& volume, const Vec3& p, const Vec3& normal, double radius,
                                double& distance, Vec3& fittedNormal) noexcept {
  const double h = volume.Spacing();
  const Vec3 foot = p - normal * radius;  // where the burr's surface meets the bone
  constexpr int MaxSamples = 125;
  Vec3 xs[MaxSamples];
  double sds[MaxSamples];
  int n = 0;
  const Vec3 reach = Splat(2.0 * h);
  const DrillGrid& grid = volume.Grid();
  volume.ForEachBlock(volume.BoxAround(foot - reach, foot + reach), [&](int32_t slot, const int lo[3], const int hi[3]) {
    const std::atomic<uint8_t>* densities = volume.BlockDensities(slot);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const uint8_t q = densities[DrillVolume::Local(i, j, k)].load(std::memory_order_relaxed);
          if (q == 0 || q == 255 || n == MaxSamples) continue;  // only the ramp knows where the surface is
          xs[n] = grid.Center(i, j, k) - foot;
          sds[n] = (0.5 - q / 255.0) * 2.0 * h;
          ++n;
        }
  });
  if (n < 4) return false;
  // The ramp of a plane is exactly linear: sd ≈ g·x + c. With samples in two or more layers
  // across the surface, fit g and c (least squares); with one layer (a surface through the
  // voxel centres), keep the contact normal and fit the offset only.
  double spread = 0, mean = 0;
  for (int s = 0; s < n; ++s) mean += Dot(xs[s], normal) / n;
  for (int s = 0; s < n; ++s) spread += std::pow(Dot(xs[s], normal) - mean, 2) / n;
  Vec3 g = normal;
  double c = 0;
  if (n >= 8 && spread > 0.04 * h * h) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    for (int s = 0; s < n; ++s) {
      const Eigen::Vector4d row(xs[s].x / h, xs[s].y / h, xs[s].z / h, 1.0);
      A += row * row.transpose();
      b += row * sds[s];
    }
    const Eigen::Vector4d x = A.ldlt().solve(b);
    if (!x.allFinite()) return false;
    g = Vec3{x[0] / h, x[1] / h, x[2] / h};
    c = x[3];
  } else {
    for (int s = 0; s < n; ++s) c += (sds[s] - Dot(normal, xs[s])) / n;
  }
  const double length = Norm(g);
  if (length < 0.7 || length > 1.3 || Dot(g, normal) < 0.7 * length) return false;
  double residual = 0;
  for (int s = 0; s < n; ++s) {
    const double e = Dot(g, xs[s]) + c - sds[s];
    residual += e * e;
  }
  if (std::sqrt(residual / n) > 0.1 * h) return false;  // not planar here (an edge, a corner)
  fittedNormal = g / length;
  distance = (Dot(g, p - foot) + c) / length;
  return true;
}

const BurrContact& BurrProxy::Update(const DrillVolume& volume, const Vec3& hip, double radius) noexcept {
  const double h = volume.Spacing();
  BurrContact& s = this->State;
  s = BurrContact{};
  Vec3 p = this->P;
  const Vec3& goal = hip;
  Vec3 target = goal;
  Vec3 planes[3];
  int n = 0;
  BurrContact touch;
  bool touchValid = false;  // `touch` is the contact at p
  // The shell's densities at p, from the last Touching: the next pass's sweep starts there, at
  // the same points of the same volume (up to a third of a sliding tick's samples).
  double shell[ShellPoints];
  const double still = 1e-3 * h;  // moves shorter than this are not worth a sweep
  for (int pass = 0; pass < 4; ++pass) {
    const Vec3 d = target - p;
    if (Norm2(d) < still * still) break;
    double overlap = 0;
    const double t = Sweep(volume, p, target, radius, overlap, touchValid ? shell : nullptr);
    if (pass == 0 && overlap > EmbeddedDepth * h) {
      // Inside bone (material came back around the burr): let it go until it is out again.
      this->P = goal;
      s.Embedded = true;
      s.Anchor = goal;
      return s;
    }
    if (t > 1) {
      p = target;  // free move
      touchValid = false;
      break;
    }
    if (n == 3) break;  // a corner
    if (t > 0 || !touchValid) {
      p = p + d * t;
      touchValid = Touching(volume, p, radius, goal - p, touch, shell);
    }
    if (!touchValid || Norm2(touch.Normal) == 0) break;
    // Blocked where it stood by the same contact as before: no other way to go.
    bool known = false;
    for (int i = 0; i < n; ++i) known = known || Dot(planes[i], touch.Normal) > 0.9999;
    if (t <= 0 && known) break;
    planes[n++] = touch.Normal;
    if (n == 1) {
      const double into = Dot(goal - p, planes[0]);
      if (into >= 0) break;  // blocked by voxels the normal puts behind: stay
      // Static friction of the bone (materials.json): inside the cone the burr does not slide.
      const Vec3 tangential = goal - p - planes[0] * into;
      const auto& materials = volume.Materials();
      const double mu = touch.Material > 0 && size_t(touch.Material) <= materials.size()
                            ? materials[touch.Material - 1].StaticFriction
                            : 0.0;
      if (Norm(tangential) <= -mu * into) break;
      target = goal - planes[0] * into;
    } else if (n == 2) {
      // The newest plane alone may be the only constraint (sliding off the first).
      const double into = Dot(goal - p, planes[1]);
      const Vec3 alone = into < 0 ? goal - planes[1] * into : goal;
      const Vec3 edge = Cross(planes[0], planes[1]);
      if (Dot(alone - p, planes[0]) >= 0) {
        planes[0] = planes[1];
        n = 1;
        target = alone;
      } else if (Norm2(edge) < 1e-8) {
        n = 1;
        target = alone;
      } else {
        const Vec3 dir = Normalized(edge);  // slide along the crease
        target = p + dir * Dot(goal - p, dir);
      }
    } else {
      const double into = Dot(goal - p, planes[2]);
      const Vec3 alone = into < 0 ? goal - planes[2] * into : goal;
      if (Dot(alone - p, planes[0]) >= 0 && Dot(alone - p, planes[1]) >= 0) {
        planes[0] = planes[2];
        n = 1;
        target = alone;
      } else {
        break;  // a corner
      }
    }
  }
  this->P = p;
  if (touchValid)
    s = touch;
  else
    Touching(volume, p, radius, goal - p, s);
  s.Planes = n;
  s.Anchor = p;
  // The exact contact (for the force) only where the hand presses into the bone.
  if (s.InContact && Norm2(s.Normal) > 0 && Dot(goal - p, s.Normal) < 0) {
    double distance;
    Vec3 fitted;
    if (SurfaceDistance(volume, p, s.Normal, radius, distance, fitted) && std::fabs(radius - distance) < h) {
      s.Anchor = p + fitted * (radius - distance);
      s.Refined = true;
    }
  }
  return s;
}

}  // namespace rp
