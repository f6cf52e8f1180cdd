// The analytic knee: capsules, spheres, rounded cylinders and ellipsoids combined by smooth
// unions, each with a closed-form signed distance (Quilez's formulas). Kept for tests that need
// exact answers; the default phantom is the real knee (rpKneeSurfaceModel.cxx).
#include <algorithm>
#include <cmath>

#include "rpKneePhantom.h"

namespace rp {
namespace {

struct V3 {
  double x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double Dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double Length(V3 a) { return std::sqrt(Dot(a, a)); }
// std::hypot guards against overflow we cannot have here, and is several times slower.
inline double Hypot(double a, double b) { return std::sqrt(a * a + b * b); }

double Capsule(V3 p, V3 a, V3 b, double r) {
  const V3 pa = p - a, ba = b - a;
  const double h = std::clamp(Dot(pa, ba) / Dot(ba, ba), 0.0, 1.0);
  return Length(pa - ba * h) - r;
}
double Sphere(V3 p, V3 c, double r) { return Length(p - c) - r; }
// Ellipsoid: a first-order bound, exact on the surface, accurate close to it.
double Ellipsoid(V3 p, V3 c, V3 r) {
  const V3 q = p - c;
  const double k0 = Length({q.x / r.x, q.y / r.y, q.z / r.z});
  const double k1 = Length({q.x / (r.x * r.x), q.y / (r.y * r.y), q.z / (r.z * r.z)});
  if (k1 < 1e-12) return -std::min({r.x, r.y, r.z});
  return k0 * (k0 - 1.0) / k1;
}
// Vertical capped cylinder centred at c, radius r, half-height h, edges rounded by e.
double RoundedCylinder(V3 p, V3 c, double r, double h, double e) {
  const V3 q = p - c;
  const double dx = Hypot(q.x, q.y) - (r - e);
  const double dz = std::abs(q.z) - (h - e);
  return std::min(std::max(dx, dz), 0.0) + Hypot(std::max(dx, 0.0), std::max(dz, 0.0)) - e;
}
double SmoothUnion(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
double Subtract(double a, double b) { return std::max(a, -b); }

constexpr double kCortical = 2.0;
constexpr double kCartilage = 2.5;
// The leg's cross-section: an ellipse (wider medio-laterally), skin 2 mm, and subcutaneous fat
// down to an inner ellipse that is off-centre (thicker fat posteriorly and medially), so the
// outline alone does not look the same after a rotation about the leg's axis.
const V3 kBodyCentre = {0.0, -4.0, 0.0};
constexpr double kBodyRx = 64.0, kBodyRy = 56.0;
const V3 kMuscleCentre = {2.0, -1.0, 0.0};
constexpr double kMuscleRx = 54.0, kMuscleRy = 44.0;

// 2D ellipse (infinite along z): first-order distance, exact on the curve.
double EllipticCylinder(V3 p, V3 c, double rx, double ry) {
  const double x = p.x - c.x, y = p.y - c.y;
  const double k0 = Hypot(x / rx, y / ry);
  const double k1 = Hypot(x / (rx * rx), y / (ry * ry));
  if (k1 < 1e-12) return -std::min(rx, ry);
  return k0 * (k0 - 1.0) / k1;
}
// The leg is not a cylinder: the thigh is wider than the knee and the calf bulges below it
// (this also tells a registration where along the leg it is).
double LegScale(double z) {
  return 1.0 + 0.10 * std::tanh((z - 20.0) / 50.0) + 0.08 * std::exp(-((z + 90.0) / 40.0) * ((z + 90.0) / 40.0));
}
double Body(V3 p) {
  const double s = LegScale(p.z);
  return EllipticCylinder(p, kBodyCentre, kBodyRx * s, kBodyRy * s);
}
double MuscleCompartment(V3 p) {
  const double s = LegScale(p.z);
  return EllipticCylinder(p, kMuscleCentre, kMuscleRx * s, kMuscleRy * s);
}
// Fat pads: popliteal (behind the knee) and infrapatellar (Hoffa's, in front of the joint).
double FatPads(V3 p) {
  return std::min(Ellipsoid(p, {0, -32, 8}, {18, 11, 42}), Ellipsoid(p, {0, 21, -7}, {14, 7, 8}));
}

double Femur(V3 p) {
  const double shaft = Capsule(p, {0, -2, 40}, {0, -2, 400}, 14.0);
  const double condyles = Capsule(p, {-22, -4, 19}, {22, -4, 19}, 19.0);
  const double notch = Capsule(p, {0, -45, 6}, {0, 4, 6}, 8.0);
  return Subtract(SmoothUnion(shaft, condyles, 16.0), notch);
}
double Tibia(V3 p) {
  const double plateau = SmoothUnion(RoundedCylinder(p, {-16, -4, -21}, 22.0, 15.0, 3.0),
                                     RoundedCylinder(p, {16, -4, -21}, 22.0, 15.0, 3.0), 8.0);
  const double shaft = Capsule(p, {0, -2, -30}, {0, -2, -400}, 14.0);
  return SmoothUnion(plateau, shaft, 16.0);
}
double Fibula(V3 p) {
  return SmoothUnion(Sphere(p, {34, -20, -48}, 9.0), Capsule(p, {34, -20, -48}, {31, -22, -400}, 7.0),
                     6.0);
}
double Patella(V3 p) { return Ellipsoid(p, {0, 28, 30}, {20, 9, 22}); }

// Cartilage: a kCartilage-thick layer on the bone, restricted to the articular region.
double Cap(double bone, double region) { return std::max({bone - kCartilage, -bone, region}); }
double FemoralCartilage(V3 p) {
  const double region = std::min(p.z - 22.0, std::max(5.0 - p.y, p.z - 45.0));
  return Cap(Femur(p), region);
}
double TibialCartilage(V3 p) { return Cap(Tibia(p), -8.0 - p.z); }
double PatellarCartilage(V3 p) { return Cap(Patella(p), p.y - 26.0); }

double ACL(V3 p) { return Capsule(p, {10, -14, 8}, {-4, 8, -6}, 4.0); }
double PCL(V3 p) { return Capsule(p, {-9, 2, 8}, {0, -20, -10}, 5.0); }
double MCL(V3 p) { return Capsule(p, {-44, -6, 22}, {-41, -2, -50}, 2.5); }
double LCL(V3 p) { return Capsule(p, {44, -8, 20}, {36, -20, -40}, 2.5); }

constexpr double kFar = 1e9;

}  // namespace

double KneeAnalyticModel::SignedDistance(KneeStructure structure, const double ras[3]) const {
  const V3 p = {ras[0], ras[1], ras[2]};
  switch (structure) {
    case KneeStructure::Femur: return Femur(p);
    case KneeStructure::Tibia: return Tibia(p);
    case KneeStructure::Fibula: return Fibula(p);
    case KneeStructure::Patella: return Patella(p);
    case KneeStructure::FemurMarrow: return Femur(p) + kCortical;
    case KneeStructure::TibiaMarrow: return Tibia(p) + kCortical;
    case KneeStructure::FibulaMarrow: return Fibula(p) + kCortical;
    case KneeStructure::PatellaMarrow: return Patella(p) + kCortical;
    case KneeStructure::FemoralCartilage: return FemoralCartilage(p);
    case KneeStructure::TibialCartilage: return TibialCartilage(p);
    case KneeStructure::PatellarCartilage: return PatellarCartilage(p);
    case KneeStructure::ACL: return ACL(p);
    case KneeStructure::PCL: return PCL(p);
    case KneeStructure::MCL: return MCL(p);
    case KneeStructure::LCL: return LCL(p);
    case KneeStructure::Body: return Body(p);
    case KneeStructure::MuscleCompartment: return MuscleCompartment(p);
    case KneeStructure::FatPads: return FatPads(p);
  }
  return kFar;
}

// Boxes holding each solid with a margin of several millimetres (the shafts and the leg run on
// along z; the smooth unions bulge up to k/4 beyond their parts).
void KneeAnalyticModel::Bounds(KneeStructure structure, double bounds[6]) const {
  auto set = [bounds](std::array<double, 6> b) { std::copy(b.begin(), b.end(), bounds); };
  switch (structure) {
    case KneeStructure::Femur: case KneeStructure::FemurMarrow: case KneeStructure::FemoralCartilage:
      return set({-50, 50, -32, 24, -9, kFar});
    case KneeStructure::Tibia: case KneeStructure::TibiaMarrow: case KneeStructure::TibialCartilage:
      return set({-47, 47, -35, 27, -kFar, 3});
    case KneeStructure::Fibula: case KneeStructure::FibulaMarrow: return set({15, 52, -38, -2, -kFar, -30});
    case KneeStructure::Patella: case KneeStructure::PatellaMarrow: case KneeStructure::PatellarCartilage:
      return set({-28, 28, 11, 45, 0, 60});
    case KneeStructure::ACL: return set({-16, 22, -26, 20, -18, 20});
    case KneeStructure::PCL: return set({-22, 13, -33, 15, -23, 21});
    case KneeStructure::MCL: return set({-55, -30, -17, 9, -61, 33});
    case KneeStructure::LCL: return set({25, 55, -31, 3, -51, 31});
    case KneeStructure::Body: return set({-80, 80, -75, 70, -kFar, kFar});
    case KneeStructure::MuscleCompartment: return set({-70, 74, -60, 58, -kFar, kFar});
    case KneeStructure::FatPads: return set({-26, 26, -51, 36, -42, 58});
  }
  set({0, 0, 0, 0, 0, 0});
}

}  // namespace rp
