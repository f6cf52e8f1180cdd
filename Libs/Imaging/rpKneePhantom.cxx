#include "rpKneePhantom.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <thread>

#include <vtkTransform.h>

namespace rp {
namespace {

struct V3 {
  double x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double Dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double Length(V3 a) { return std::sqrt(Dot(a, a)); }
// std::hypot guards against overflow we cannot have here, and is several times slower.
inline double Hypot(double a, double b) { return std::sqrt(a * a + b * b); }

// Exact signed distances of the primitives (Quilez's formulas) and the CSG combinations.
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
constexpr double kSkin = 2.0;
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
double PoplitealFat(V3 p) { return Ellipsoid(p, {0, -32, 8}, {18, 11, 42}); }
double HoffaFat(V3 p) { return Ellipsoid(p, {0, 21, -7}, {14, 7, 8}); }

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

struct StructureBox {
  double b[6];
};
// Generous boxes for surface sampling (the long shafts are cut at |z| = 160 mm).
StructureBox BoxOf(KneeStructure s) {
  switch (s) {
    case KneeStructure::Femur: case KneeStructure::FemurMarrow: case KneeStructure::FemoralCartilage:
      return {{-45, 45, -25, 25, -5, 160}};
    case KneeStructure::Tibia: case KneeStructure::TibiaMarrow: case KneeStructure::TibialCartilage:
      return {{-42, 42, -30, 22, -160, 0}};
    case KneeStructure::Fibula: case KneeStructure::FibulaMarrow:
      return {{20, 48, -34, -6, -160, -35}};
    case KneeStructure::Patella: case KneeStructure::PatellaMarrow: case KneeStructure::PatellarCartilage:
      return {{-23, 23, 16, 40, 5, 55}};
    case KneeStructure::ACL: return {{-10, 16, -20, 14, -12, 14}};
    case KneeStructure::PCL: return {{-16, 7, -27, 9, -17, 15}};
    case KneeStructure::MCL: return {{-48, -37, -10, 2, -54, 26}};
    case KneeStructure::LCL: return {{31, 48, -24, -4, -44, 24}};
    case KneeStructure::Body: return {{-80, 80, -75, 70, -160, 160}};
  }
  return {{0, 0, 0, 0, 0, 0}};
}

}  // namespace

const std::vector<KneeTissue>& KneeTissues() {
  static const std::vector<KneeTissue> tissues = {
      {KneeBackground, "air", "air", -1000, 0, {0, 0, 0}},
      {KneeSkin, "skin", "skin", 30, 450, {0.95, 0.78, 0.66}},
      {KneeFat, "fat", "fat", -100, 900, {0.98, 0.9, 0.55}},
      {KneeMuscle, "muscle", "muscle", 50, 350, {0.75, 0.3, 0.25}},
      {KneeFemurCortical, "femur cortical", "bone", 1300, 40, {0.95, 0.93, 0.85}},
      {KneeFemurTrabecular, "femur trabecular", "bone", 300, 720, {0.9, 0.82, 0.65}},
      {KneeTibiaCortical, "tibia cortical", "bone", 1300, 40, {0.95, 0.93, 0.85}},
      {KneeTibiaTrabecular, "tibia trabecular", "bone", 300, 720, {0.9, 0.82, 0.65}},
      {KneeFibulaCortical, "fibula cortical", "bone", 1250, 40, {0.95, 0.93, 0.85}},
      {KneeFibulaTrabecular, "fibula trabecular", "bone", 280, 720, {0.9, 0.82, 0.65}},
      {KneePatellaCortical, "patella cortical", "bone", 1200, 40, {0.95, 0.93, 0.85}},
      {KneePatellaTrabecular, "patella trabecular", "bone", 320, 720, {0.9, 0.82, 0.65}},
      {KneeFemoralCartilage, "femoral cartilage", "cartilage", 110, 620, {0.55, 0.75, 0.95}},
      {KneeTibialCartilage, "tibial cartilage", "cartilage", 110, 620, {0.55, 0.75, 0.95}},
      {KneePatellarCartilage, "patellar cartilage", "cartilage", 110, 620, {0.55, 0.75, 0.95}},
      {KneeACL, "ACL", "ligament", 85, 90, {0.4, 0.8, 0.4}},
      {KneePCL, "PCL", "ligament", 85, 90, {0.3, 0.7, 0.3}},
      {KneeMCL, "MCL", "ligament", 85, 90, {0.45, 0.85, 0.5}},
      {KneeLCL, "LCL", "ligament", 85, 90, {0.35, 0.75, 0.45}},
  };
  return tissues;
}

KneeModel::KneeModel() = default;

double KneeModel::SignedDistance(KneeStructure structure, const double ras[3]) const {
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
  }
  return 1e9;
}

namespace {
// Boxes that contain each solid with a margin: outside its box a solid's distance is at least
// the margin, so it need not be evaluated (most of a large volume is far from most solids).
struct CullBox {
  double lo[3], hi[3];
};
constexpr double kMargin = 8.0;
constexpr double kFar = 1e9;
inline double Bounded(V3 p, const CullBox& b, double (*sdf)(V3)) {
  const double q[3] = {p.x, p.y, p.z};
  for (int a = 0; a < 3; ++a)
    if (q[a] < b.lo[a] || q[a] > b.hi[a]) return kMargin;  // lower bound of the true distance
  return sdf(p);
}
const CullBox kFemurBox = {{-50, -32, -9}, {50, 24, kFar}};
const CullBox kTibiaBox = {{-47, -35, -kFar}, {47, 27, 3}};
const CullBox kFibulaBox = {{15, -38, -kFar}, {52, -2, -30}};
const CullBox kPatellaBox = {{-28, 11, 0}, {28, 45, 60}};
const CullBox kACLBox = {{-16, -26, -18}, {22, 20, 20}};
const CullBox kPCLBox = {{-22, -33, -23}, {13, 15, 21}};
const CullBox kMCLBox = {{-55, -17, -61}, {-30, 9, 33}};
const CullBox kLCLBox = {{25, -31, -51}, {55, 3, 31}};
const CullBox kPoplitealBox = {{-26, -51, -42}, {26, -13, 58}};
const CullBox kHoffaBox = {{-22, 6, -23}, {22, 36, 9}};

// The labelmap rule. `boundary` (optional) receives the smallest |signed distance| of the
// surfaces tested, so callers know when a voxel straddles a boundary (partial volume).
KneeLabel Classify(V3 p, double* boundary) {
  double nearest = 1e9;
  auto track = [&](double d) {
    nearest = std::min(nearest, std::abs(d));
    return d;
  };
  auto finish = [&](KneeLabel label) {
    if (boundary) *boundary = nearest;
    return label;
  };
  const double body = track(Body(p));
  if (body > 0.0) return finish(KneeBackground);
  if (body > -kSkin) {
    track(body + kSkin);
    return finish(KneeSkin);
  }
  track(body + kSkin);
  // Bones, cartilage, ligaments and fat pads live inside the muscle compartment only.
  const double compartment = track(MuscleCompartment(p));
  if (compartment > 0.0) return finish(KneeFat);
  {
    struct Bone {
      double d;
      KneeLabel cortical, trabecular;
    };
    const Bone bones[4] = {{Bounded(p, kPatellaBox, Patella), KneePatellaCortical, KneePatellaTrabecular},
                           {Bounded(p, kFemurBox, Femur), KneeFemurCortical, KneeFemurTrabecular},
                           {Bounded(p, kTibiaBox, Tibia), KneeTibiaCortical, KneeTibiaTrabecular},
                           {Bounded(p, kFibulaBox, Fibula), KneeFibulaCortical, KneeFibulaTrabecular}};
    for (const Bone& bone : bones) {
      track(bone.d);
      track(bone.d + kCortical);
      track(bone.d - kCartilage);
    }
    for (const Bone& bone : bones) {
      if (bone.d < 0.0) return finish(bone.d > -kCortical ? bone.cortical : bone.trabecular);
    }
    // Cartilage caps: reuse the bone distances.
    const double femoralRegion = std::min(p.z - 22.0, std::max(5.0 - p.y, p.z - 45.0));
    const double caps[3] = {Cap(bones[1].d, femoralRegion), Cap(bones[2].d, -8.0 - p.z),
                            Cap(bones[0].d, p.y - 26.0)};
    const KneeLabel capLabels[3] = {KneeFemoralCartilage, KneeTibialCartilage, KneePatellarCartilage};
    for (int i = 0; i < 3; ++i) {
      if (track(caps[i]) < 0.0) return finish(capLabels[i]);
    }
    const double ligaments[4] = {Bounded(p, kACLBox, ACL), Bounded(p, kPCLBox, PCL), Bounded(p, kMCLBox, MCL),
                                 Bounded(p, kLCLBox, LCL)};
    const KneeLabel ligamentLabels[4] = {KneeACL, KneePCL, KneeMCL, KneeLCL};
    for (int i = 0; i < 4; ++i) {
      if (track(ligaments[i]) < 0.0) return finish(ligamentLabels[i]);
    }
  }
  if (track(Bounded(p, kPoplitealBox, PoplitealFat)) < 0.0 || track(Bounded(p, kHoffaBox, HoffaFat)) < 0.0)
    return finish(KneeFat);
  return finish(KneeMuscle);
}
}  // namespace

KneeLabel KneeModel::LabelAt(const double ras[3]) const { return Classify({ras[0], ras[1], ras[2]}, nullptr); }

std::vector<std::array<double, 3>> KneeModel::SurfacePoints(KneeStructure structure, int count,
                                                            const double* boundsRAS) const {
  std::vector<std::array<double, 3>> points;
  if (count <= 0) return points;
  StructureBox box = BoxOf(structure);
  if (boundsRAS) {
    for (int a = 0; a < 3; ++a) {
      box.b[2 * a] = std::max(box.b[2 * a], boundsRAS[2 * a]);
      box.b[2 * a + 1] = std::min(box.b[2 * a + 1], boundsRAS[2 * a + 1]);
      if (box.b[2 * a] >= box.b[2 * a + 1]) return points;
    }
  }
  std::mt19937 rng(12345u + static_cast<unsigned>(structure));
  std::uniform_real_distribution<double> ux(box.b[0], box.b[1]), uy(box.b[2], box.b[3]), uz(box.b[4], box.b[5]);
  const double band = 1.0;  // uniform samples in a thin shell → roughly uniform on the surface
  points.reserve(count);
  const long maxTries = 4000L * count + 100000L;
  for (long tries = 0; tries < maxTries && static_cast<int>(points.size()) < count; ++tries) {
    double p[3] = {ux(rng), uy(rng), uz(rng)};
    if (std::abs(this->SignedDistance(structure, p)) > band) continue;
    // Newton projection along the numerical gradient.
    bool converged = false;
    for (int it = 0; it < 20 && !converged; ++it) {
      const double d = this->SignedDistance(structure, p);
      if (std::abs(d) < 0.005) {
        converged = true;
        break;
      }
      double g[3];
      const double h = 1e-4;
      for (int a = 0; a < 3; ++a) {
        double q1[3] = {p[0], p[1], p[2]}, q0[3] = {p[0], p[1], p[2]};
        q1[a] += h;
        q0[a] -= h;
        g[a] = (this->SignedDistance(structure, q1) - this->SignedDistance(structure, q0)) / (2 * h);
      }
      const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
      if (gg < 1e-12) break;
      for (int a = 0; a < 3; ++a) p[a] -= d * g[a] / gg;
    }
    if (!converged) continue;
    bool inBox = true;
    for (int a = 0; a < 3; ++a) inBox = inBox && p[a] >= box.b[2 * a] && p[a] <= box.b[2 * a + 1];
    if (inBox) points.push_back({p[0], p[1], p[2]});
  }
  return points;
}

namespace {

struct Grid {
  int dims[3];
  double spacing[3];
  double axes[3][3];  // unit direction (RAS) of i, j, k
  double origin[3];   // RAS of voxel (0,0,0)
};

vtkSmartPointer<vtkMatrix4x4> MatrixOf(const Grid& g) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m->SetElement(r, c, g.axes[c][r] * g.spacing[c]);
    m->SetElement(c, 3, g.origin[c]);
  }
  return m;
}

// Centres a grid on `centre` given its axes.
void CentreGrid(Grid& g, const double centre[3]) {
  for (int r = 0; r < 3; ++r) {
    g.origin[r] = centre[r];
    for (int c = 0; c < 3; ++c) g.origin[r] -= g.axes[c][r] * g.spacing[c] * (g.dims[c] - 1) * 0.5;
  }
}

vtkSmartPointer<vtkImageData> Allocate(const Grid& g, int scalarType) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  image->AllocateScalars(scalarType, 1);
  return image;
}

// Runs `slice(k)` for every slice on two threads; progress is reported from the calling thread.
template <typename SliceFn>
void ForEachSlice(int slices, SliceFn slice, const ProgressCallback& progress, double from, double to,
                  const std::string& message) {
  std::atomic<int> next{0}, done{0};
  auto worker = [&]() {
    for (int k = next++; k < slices; k = next++) {
      slice(k);
      ++done;
    }
  };
  const unsigned hw = std::max(1u, std::min(2u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < hw; ++t) threads.emplace_back(worker);
  for (int k = next++; k < slices; k = next++) {
    slice(k);
    ++done;
    if (progress) progress(from + (to - from) * done.load() / slices, message);
  }
  for (auto& t : threads) t.join();
  if (progress) progress(to, message);
}

// Partial volume: a voxel that straddles a boundary averages 2x2x2 sub-samples.
template <typename Value>
double SampleVoxel(V3 centre, const V3 sub[3], double halfDiagonal, Value value, KneeLabel* centreLabel = nullptr) {
  double boundary = 0.0;
  const KneeLabel label = Classify(centre, &boundary);
  if (centreLabel) *centreLabel = label;
  if (boundary >= halfDiagonal) return value(label);
  double sum = 0.0;
  for (int s = 0; s < 8; ++s) {
    const double fi = (s & 1) ? 0.25 : -0.25, fj = (s & 2) ? 0.25 : -0.25, fk = (s & 4) ? 0.25 : -0.25;
    const V3 q = centre + sub[0] * fi + sub[1] * fj + sub[2] * fk;
    sum += value(Classify(q, nullptr));
  }
  return sum / 8.0;
}

}  // namespace

bool GenerateKneePhantom(const KneePhantomOptions& options, KneePhantom& phantom, std::string& error,
                         const ProgressCallback& progress) {
  try {
    Grid ct{};
    Grid mr{};
    const bool explicitGrid = options.CTDimensions[0] > 0 && options.CTDimensions[1] > 0 &&
                              options.CTDimensions[2] > 0;
    if (explicitGrid) {
      for (int a = 0; a < 3; ++a) {
        if (!(options.CTSpacing[a] > 0.0)) {
          error = "knee phantom: explicit CT dimensions need a positive CT spacing";
          return false;
        }
        if (options.CTDimensions[a] > 2048) {
          error = "knee phantom: CT dimension above 2048";
          return false;
        }
        ct.dims[a] = options.CTDimensions[a];
        ct.spacing[a] = options.CTSpacing[a];
      }
    } else if (options.Size == KneePhantomSize::Full) {
      ct = {{512, 512, 300}, {0.3, 0.3, 1.0}, {}, {}};
    } else {
      ct = {{96, 96, 64}, {1.6, 1.6, 2.5}, {}, {}};
    }
    const bool full = !explicitGrid && options.Size == KneePhantomSize::Full;
    // CT: axial, DICOM's usual LPS identity directions → RAS i = -x, j = -y, k = +z.
    const double ctAxes[3][3] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
    std::copy(&ctAxes[0][0], &ctAxes[0][0] + 9, &ct.axes[0][0]);
    const double zero[3] = {0, 0, 0};
    CentreGrid(ct, zero);
    // MR: sagittal proton density, 1.7 mm slices. LPS IOP (0,1,0 / 0,0,-1) → RAS i = -y,
    // j = -z, slice normal k = +x.
    mr = full ? Grid{{384, 384, 90}, {0.4, 0.4, 1.7}, {}, {}} : Grid{{96, 96, 84}, {1.6, 1.6, 1.7}, {}, {}};
    const double mrAxes[3][3] = {{0, -1, 0}, {0, 0, -1}, {1, 0, 0}};
    std::copy(&mrAxes[0][0], &mrAxes[0][0] + 9, &mr.axes[0][0]);
    const double mrCentre[3] = {2.0, -3.0, 4.0};  // the MR's isocentre is not the CT's
    CentreGrid(mr, mrCentre);

    auto model = std::make_shared<KneeModel>();
    phantom.Model = model;
    vtkNew<vtkTransform> pose;
    pose->PostMultiply();
    pose->RotateX(options.MRRotationDegrees[0]);
    pose->RotateY(options.MRRotationDegrees[1]);
    pose->RotateZ(options.MRRotationDegrees[2]);
    pose->Translate(options.MRTranslation[0], options.MRTranslation[1], options.MRTranslation[2]);
    phantom.CTToMR->DeepCopy(pose->GetMatrix());
    vtkNew<vtkMatrix4x4> mrToCT;
    vtkMatrix4x4::Invert(phantom.CTToMR, mrToCT);

    const auto& tissues = KneeTissues();
    double stage = 0.0;
    const double stages = (options.GenerateCT ? 1 : 0) + (options.GenerateMR ? 1 : 0) + (options.GenerateLabels ? 0.5 : 0);
    auto span = [&](double w) {
      const double from = stage / std::max(stages, 1.0);
      stage += w;
      return std::make_pair(from, stage / std::max(stages, 1.0));
    };

    auto voxelCentre = [](const Grid& g, int i, int j, int k) {
      V3 p = {g.origin[0], g.origin[1], g.origin[2]};
      const int idx[3] = {i, j, k};
      for (int c = 0; c < 3; ++c) p = p + V3{g.axes[c][0], g.axes[c][1], g.axes[c][2]} * (idx[c] * g.spacing[c]);
      return p;
    };

    // CT and labels in one pass (the label is the classification of the voxel centre).
    unsigned char* labelsOut = nullptr;
    if (options.GenerateLabels) {
      phantom.Labels.Image = Allocate(ct, VTK_UNSIGNED_CHAR);
      phantom.Labels.IJKToRAS = MatrixOf(ct);
      phantom.Labels.Modality = "SEG";
      phantom.Labels.Description = "RoboPlan knee phantom ground truth";
      labelsOut = static_cast<unsigned char*>(phantom.Labels.Image->GetScalarPointer());
    }
    if (options.GenerateCT) {
      phantom.CT.Image = Allocate(ct, VTK_SHORT);
      phantom.CT.IJKToRAS = MatrixOf(ct);
      phantom.CT.Window = 2000;
      phantom.CT.Level = 400;
      phantom.CT.Modality = "CT";
      phantom.CT.Description = "RoboPlan knee phantom CT";
      short* out = static_cast<short*>(phantom.CT.Image->GetScalarPointer());
      V3 sub[3];
      for (int c = 0; c < 3; ++c) sub[c] = V3{ct.axes[c][0], ct.axes[c][1], ct.axes[c][2]} * ct.spacing[c];
      const double halfDiagonal = 0.5 * std::sqrt(Dot(sub[0], sub[0]) + Dot(sub[1], sub[1]) + Dot(sub[2], sub[2]));
      auto hu = [&](KneeLabel l) { return tissues[l].CTHounsfield; };
      const auto range = span(options.GenerateLabels ? 1.5 : 1.0);
      ForEachSlice(
          ct.dims[2],
          [&](int k) {
            std::mt19937 rng(options.Seed * 2654435761u + 17u * static_cast<unsigned>(k) + 1u);
            std::normal_distribution<double> noise(0.0, options.CTNoiseHU);
            const size_t offset = static_cast<size_t>(k) * ct.dims[0] * ct.dims[1];
            short* row = out + offset;
            unsigned char* labelRow = labelsOut ? labelsOut + offset : nullptr;
            for (int j = 0; j < ct.dims[1]; ++j) {
              for (int i = 0; i < ct.dims[0]; ++i) {
                KneeLabel label;
                double v = SampleVoxel(voxelCentre(ct, i, j, k), sub, halfDiagonal, hu, &label);
                if (v > -1000.0) v += noise(rng);  // air stays at -1000 (outside the scanner's noise floor)
                *row++ = static_cast<short>(std::lround(std::clamp(v, -1024.0, 3071.0)));
                if (labelRow) *labelRow++ = label;
              }
            }
          },
          progress, range.first, range.second, "CT");
    } else if (options.GenerateLabels) {
      const auto range = span(0.5);
      ForEachSlice(
          ct.dims[2],
          [&](int k) {
            unsigned char* row = labelsOut + static_cast<size_t>(k) * ct.dims[0] * ct.dims[1];
            for (int j = 0; j < ct.dims[1]; ++j)
              for (int i = 0; i < ct.dims[0]; ++i) *row++ = Classify(voxelCentre(ct, i, j, k), nullptr);
          },
          progress, range.first, range.second, "labels");
    }

    if (options.GenerateMR) {
      phantom.MR.Image = Allocate(mr, VTK_UNSIGNED_SHORT);
      phantom.MR.IJKToRAS = MatrixOf(mr);
      phantom.MR.Window = 1000;
      phantom.MR.Level = 500;
      phantom.MR.Modality = "MR";
      phantom.MR.Description = "RoboPlan knee phantom PD";
      unsigned short* out = static_cast<unsigned short*>(phantom.MR.Image->GetScalarPointer());
      // The MR grid in anatomy (CT) coordinates: the knee moved by CTToMR.
      Grid anatomy = mr;
      double o[4] = {mr.origin[0], mr.origin[1], mr.origin[2], 1.0};
      mrToCT->MultiplyPoint(o, o);
      for (int r = 0; r < 3; ++r) anatomy.origin[r] = o[r];
      for (int c = 0; c < 3; ++c) {
        double a[4] = {mr.axes[c][0], mr.axes[c][1], mr.axes[c][2], 0.0};
        mrToCT->MultiplyPoint(a, a);
        for (int r = 0; r < 3; ++r) anatomy.axes[c][r] = a[r];
      }
      V3 sub[3];
      for (int c = 0; c < 3; ++c)
        sub[c] = V3{anatomy.axes[c][0], anatomy.axes[c][1], anatomy.axes[c][2]} * anatomy.spacing[c];
      const double halfDiagonal = 0.5 * std::sqrt(Dot(sub[0], sub[0]) + Dot(sub[1], sub[1]) + Dot(sub[2], sub[2]));
      auto pd = [&](KneeLabel l) { return tissues[l].MRIntensity; };
      const auto range = span(1.0);
      ForEachSlice(
          mr.dims[2],
          [&](int k) {
            std::mt19937 rng(options.Seed * 2246822519u + 31u * static_cast<unsigned>(k) + 7u);
            std::normal_distribution<double> noise(0.0, options.MRNoise);
            unsigned short* row = out + static_cast<size_t>(k) * mr.dims[0] * mr.dims[1];
            for (int j = 0; j < mr.dims[1]; ++j) {
              for (int i = 0; i < mr.dims[0]; ++i) {
                const V3 p = voxelCentre(anatomy, i, j, k);
                // A gentle receive-coil bias along the leg, as in a real knee coil.
                const double bias = 1.0 - 0.15 * std::min(1.0, std::abs(p.z) / 120.0);
                const double v = SampleVoxel(p, sub, halfDiagonal, pd) * bias;
                // Rician magnitude noise: |signal + complex Gaussian|.
                const double re = v + noise(rng), im = noise(rng);
                *row++ = static_cast<unsigned short>(std::lround(std::min(Hypot(re, im), 65535.0)));
              }
            }
          },
          progress, range.first, range.second, "MR");
    }
    return true;
  } catch (const std::bad_alloc&) {
    error = "knee phantom: out of memory";
  } catch (const std::exception& e) {
    error = std::string("knee phantom: ") + e.what();
  }
  return false;
}

}  // namespace rp
