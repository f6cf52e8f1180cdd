// The real knee: the Visible Human Female's right knee as closed surfaces (shipped in
// Resources/Anatomy/KneeVHF, see its README), with the soft tissues the surfaces do not hold
// generated around the bones: the leg's skin and the muscles' outline as rounded cross-sections
// (superellipses) that follow the bones along the leg, and the two fat pads of the knee.
#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <limits>
#include <random>

#include <vtkCellArray.h>
#include <vtkPolyData.h>

#include "rpKneePhantom.h"
#include "rpMeshSignedDistance.h"
#include "rpModelIO.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpResources.h"

namespace rp {
namespace {

constexpr double kFarMm = 1e9;
constexpr int kMeshStructures = 11;
struct PartFiles {
  KneeStructure Structure;
  std::vector<const char*> Files;
};
const PartFiles kParts[kMeshStructures] = {
    {KneeStructure::Femur, {"femur.vtp"}},
    {KneeStructure::Tibia, {"tibia.vtp"}},
    {KneeStructure::Fibula, {"fibula.vtp"}},
    {KneeStructure::Patella, {"patella.vtp"}},
    {KneeStructure::FemoralCartilage, {"cartilage_femur.vtp"}},
    {KneeStructure::TibialCartilage, {"cartilage_tibia_medial.vtp", "cartilage_tibia_lateral.vtp"}},
    {KneeStructure::PatellarCartilage, {"cartilage_patella.vtp"}},
    {KneeStructure::ACL, {"ligament_acl.vtp"}},
    {KneeStructure::PCL, {"ligament_pcl.vtp"}},
    {KneeStructure::MCL, {"ligament_mcl.vtp"}},
    {KneeStructure::LCL, {"ligament_lcl.vtp"}},
};

double SmoothStep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Soft-tissue depth over the bones (mm) on each side of the leg's cross-section, at the knee,
// on the thigh and on the calf: thin over the patella and the shin, thick behind the knee
// (popliteal fossa) and around the thigh (quadriceps, hamstrings) and calf (triceps surae).
struct Margins {
  double Lateral, Medial, Anterior, Posterior;
};
constexpr Margins kKneeMargins = {12, 14, 7, 38};
constexpr Margins kThighMargins = {40, 45, 30, 50};
constexpr Margins kCalfMargins = {18, 26, 6, 52};
// Subcutaneous fat (mm) between the skin and the muscles, per side.
constexpr Margins kFat = {8, 12, 4, 10};
constexpr double kSuperellipse = 2.4;  // exponent: between an ellipse (2) and a rounded box

Margins MarginsAt(double z) {
  const double thigh = SmoothStep(20, 100, z), calf = SmoothStep(10, 90, -z);
  auto mix = [&](double knee, double t, double c) { return knee + thigh * (t - knee) + calf * (c - knee); };
  return {mix(kKneeMargins.Lateral, kThighMargins.Lateral, kCalfMargins.Lateral),
          mix(kKneeMargins.Medial, kThighMargins.Medial, kCalfMargins.Medial),
          mix(kKneeMargins.Anterior, kThighMargins.Anterior, kCalfMargins.Anterior),
          mix(kKneeMargins.Posterior, kThighMargins.Posterior, kCalfMargins.Posterior)};
}

// Cortical thickness along a long bone: thin at the joint (subchondral and metaphyseal shell),
// thick in the diaphysis.
struct Cortex {
  double Epiphysis, Diaphysis;
};
constexpr Cortex kFemurCortex = {0.9, 4.0}, kTibiaCortex = {0.9, 4.5}, kFibulaCortex = {0.8, 2.5};
constexpr double kPatellaCortex = 1.2;

// First-order signed distance to a superellipse |u/a|^n + |v/b|^n = 1 (exact on the curve).
double Superellipse(double u, double v, double a, double b, double n) {
  const double qu = std::abs(u) / a, qv = std::abs(v) / b;
  const double r = std::pow(std::pow(qu, n) + std::pow(qv, n), 1.0 / n);
  if (r < 1e-9) return -std::min(a, b);
  const double gu = std::pow(qu / r, n - 1.0) / a, gv = std::pow(qv / r, n - 1.0) / b;
  return (r - 1.0) / std::sqrt(gu * gu + gv * gv);
}

vtkSmartPointer<vtkPolyData> AppendPolyData(const std::vector<vtkSmartPointer<vtkPolyData>>& parts) {
  if (parts.size() == 1) return parts[0];
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  for (const auto& part : parts) {
    const vtkIdType offset = points->GetNumberOfPoints();
    for (vtkIdType i = 0; i < part->GetNumberOfPoints(); ++i) points->InsertNextPoint(part->GetPoint(i));
    vtkIdType n;
    const vtkIdType* ids;
    for (part->GetPolys()->InitTraversal(); part->GetPolys()->GetNextCell(n, ids);) {
      std::vector<vtkIdType> shifted(ids, ids + n);
      for (auto& id : shifted) id += offset;
      polys->InsertNextCell(n, shifted.data());
    }
  }
  out->SetPoints(points);
  out->SetPolys(polys);
  return out;
}

class KneeSurfaceModel : public KneeModel {
 public:
  bool Load(const std::string& folder, std::string& error);

  std::string Description() const override {
    return "Visible Human Female right knee (real surfaces: Andreassen et al. 2022, BMFToolkit; NLM Visible Human "
           "Project)";
  }
  double SignedDistance(KneeStructure structure, const double ras[3]) const override;
  void Bounds(KneeStructure structure, double bounds[6]) const override;
  double CorticalThickness(KneeStructure bone, const double ras[3]) const override;
  double MaxCorticalThickness() const override { return kTibiaCortex.Diaphysis; }
  void FieldOfViewCentre(double ras[3]) const override;
  bool RealisticTissue() const override { return true; }
  void KneeAxes(double lateral[3], double anterior[3]) const override {
    lateral[0] = this->AxisU[0], lateral[1] = this->AxisU[1], lateral[2] = 0;
    anterior[0] = this->AxisV[0], anterior[1] = this->AxisV[1], anterior[2] = 0;
  }
  std::vector<std::array<double, 3>> SurfacePoints(KneeStructure structure, int count,
                                                   const double* boundsRAS) const override;
  vtkSmartPointer<vtkPolyData> Surface(KneeStructure structure) const override;
  void SampleSignedDistance(KneeStructure structure, const KneeGrid& grid, const KneeGridBox& box, double band,
                            float* out) const override;

 private:
  struct Part {
    vtkSmartPointer<vtkPolyData> Poly;
    MeshSignedDistance Distance;
    std::vector<double> CumulativeArea;  // for area-weighted surface samples
  };
  // The leg's cross-section at height z, in the knee's own axes (u lateral, v anterior).
  struct Section {
    double U0, U1, V0, V1;  // bone extents
  };
  const Part* PartOf(KneeStructure s) const {
    const auto it = this->Parts.find(s);
    return it == this->Parts.end() ? nullptr : &it->second;
  }
  void ToKneeAxes(const double ras[3], double& u, double& v) const {
    u = this->AxisU[0] * ras[0] + this->AxisU[1] * ras[1];
    v = this->AxisV[0] * ras[0] + this->AxisV[1] * ras[1];
  }
  Section SectionAt(double z) const;
  double Envelope(const double ras[3], double inset(const Margins&, int side)) const;
  double FatPads(const double ras[3]) const;

  std::map<KneeStructure, Part> Parts;
  double AxisU[2] = {1, 0}, AxisV[2] = {0, 1};  // the knee's medio-lateral and antero-posterior axes in x, y
  double SectionZ0 = 0, SectionStep = 2;
  std::vector<Section> Sections;
  double LegZ[2] = {0, 0};  // z range of the bones
  struct Pad {
    double Centre[3], Radii[3];  // in (u, v, z)
  } Pads[2];
};

bool KneeSurfaceModel::Load(const std::string& folder, std::string& error) {
  std::vector<vtkSmartPointer<vtkPolyData>> plateaus;
  for (const PartFiles& files : kParts) {
    std::vector<vtkSmartPointer<vtkPolyData>> polys;
    for (const char* file : files.Files) {
      auto poly = vtkSmartPointer<vtkPolyData>::New();
      if (!ReadModelFile(folder + "/" + file, poly, error)) {
        error = "knee anatomy: " + error;
        return false;
      }
      polys.push_back(poly);
    }
    if (files.Structure == KneeStructure::TibialCartilage) plateaus = polys;  // medial, lateral
    Part& part = this->Parts[files.Structure];
    part.Poly = AppendPolyData(polys);
    TriangleMesh mesh;
    if (!PolyDataToTriangleMesh(part.Poly, nullptr, mesh, error) || !part.Distance.Build(mesh, error)) {
      error = "knee anatomy: " + std::string(files.Files[0]) + ": " + error;
      return false;
    }
    double total = 0;
    for (const auto& t : mesh.Triangles) {
      total += 0.5 * Norm(Cross(mesh.Points[t[1]] - mesh.Points[t[0]], mesh.Points[t[2]] - mesh.Points[t[0]]));
      part.CumulativeArea.push_back(total);
    }
  }
  // The knee's medio-lateral axis: from the medial to the lateral tibial cartilage (the tibial
  // plateau), in the axial plane. The leg lies rotated about z in the scanner, as patients do.
  double centres[2][2];
  for (int side = 0; side < 2; ++side) {
    double sum[2] = {0, 0};
    vtkPolyData* plateau = plateaus[side];
    for (vtkIdType i = 0; i < plateau->GetNumberOfPoints(); ++i) sum[0] += plateau->GetPoint(i)[0], sum[1] += plateau->GetPoint(i)[1];
    centres[side][0] = sum[0] / plateau->GetNumberOfPoints();
    centres[side][1] = sum[1] / plateau->GetNumberOfPoints();
  }
  const double ml[2] = {centres[1][0] - centres[0][0], centres[1][1] - centres[0][1]};
  const double length = std::hypot(ml[0], ml[1]);
  if (!(length > 10.0)) {
    error = "knee anatomy: the tibial cartilages do not give a medio-lateral axis";
    return false;
  }
  this->AxisU[0] = ml[0] / length;
  this->AxisU[1] = ml[1] / length;
  this->AxisV[0] = -this->AxisU[1];  // anterior = superior × lateral for a right knee
  this->AxisV[1] = this->AxisU[0];

  // Bone extents (u, v) per 2 mm of height, from the bones' vertices.
  double zlo = kFarMm, zhi = -kFarMm;
  for (KneeStructure s : {KneeStructure::Femur, KneeStructure::Tibia, KneeStructure::Fibula, KneeStructure::Patella}) {
    zlo = std::min(zlo, this->Parts[s].Distance.Lo().z);
    zhi = std::max(zhi, this->Parts[s].Distance.Hi().z);
  }
  this->LegZ[0] = zlo;
  this->LegZ[1] = zhi;
  this->SectionZ0 = zlo;
  const int sections = static_cast<int>(std::ceil((zhi - zlo) / this->SectionStep)) + 1;
  this->Sections.assign(sections, {kFarMm, -kFarMm, kFarMm, -kFarMm});
  for (KneeStructure s : {KneeStructure::Femur, KneeStructure::Tibia, KneeStructure::Fibula, KneeStructure::Patella}) {
    vtkPolyData* poly = this->Parts[s].Poly;
    for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
      const double* p = poly->GetPoint(i);
      double u, v;
      this->ToKneeAxes(p, u, v);
      // Each vertex widens its own section and the neighbours (vertices are ~1-3 mm apart).
      const int centre = static_cast<int>(std::lround((p[2] - zlo) / this->SectionStep));
      for (int k = std::max(0, centre - 1); k <= std::min(sections - 1, centre + 1); ++k) {
        Section& section = this->Sections[k];
        section.U0 = std::min(section.U0, u);
        section.U1 = std::max(section.U1, u);
        section.V0 = std::min(section.V0, v);
        section.V1 = std::max(section.V1, v);
      }
    }
  }
  // Smooth along the leg (the skin does not follow every bump of the bones): a running maximum
  // of the extents over ±8 mm, then a moving average over ±10 mm.
  auto smooth = [&](auto get, bool maximum) {
    std::vector<double> in(sections), out(sections);
    for (int k = 0; k < sections; ++k) in[k] = get(this->Sections[k]);
    const int reachMax = 4, reachMean = 5;
    for (int k = 0; k < sections; ++k) {
      double m = in[k];
      for (int d = -reachMax; d <= reachMax; ++d) {
        const int q = std::clamp(k + d, 0, sections - 1);
        m = maximum ? std::max(m, in[q]) : std::min(m, in[q]);
      }
      out[k] = m;
    }
    for (int k = 0; k < sections; ++k) {
      double sum = 0;
      for (int d = -reachMean; d <= reachMean; ++d) sum += out[std::clamp(k + d, 0, sections - 1)];
      get(this->Sections[k]) = sum / (2 * reachMean + 1);
    }
  };
  smooth([](Section& s) -> double& { return s.U0; }, false);
  smooth([](Section& s) -> double& { return s.U1; }, true);
  smooth([](Section& s) -> double& { return s.V0; }, false);
  smooth([](Section& s) -> double& { return s.V1; }, true);

  // Fat pads. Popliteal: behind the femoral condyles, along the leg. Infrapatellar (Hoffa's):
  // below the patella, in front of the joint.
  const Section knee = this->SectionAt(15.0);
  this->Pads[0] = {{0.5 * (knee.U0 + knee.U1), knee.V0 - 10.0, 15.0}, {14.0, 10.0, 35.0}};
  const Part& patella = this->Parts[KneeStructure::Patella];
  const double patellaLow = patella.Distance.Lo().z;
  double patellaCentre[3] = {0.5 * (patella.Distance.Lo().x + patella.Distance.Hi().x),
                             0.5 * (patella.Distance.Lo().y + patella.Distance.Hi().y), 0.0};
  double pu, pv;
  this->ToKneeAxes(patellaCentre, pu, pv);
  const Section joint = this->SectionAt(-5.0);
  this->Pads[1] = {{pu, joint.V1 - 4.0, patellaLow - 8.0}, {15.0, 8.0, 10.0}};
  return true;
}

KneeSurfaceModel::Section KneeSurfaceModel::SectionAt(double z) const {
  const double f = std::clamp((z - this->SectionZ0) / this->SectionStep, 0.0, double(this->Sections.size() - 1));
  const size_t k = std::min(static_cast<size_t>(f), this->Sections.size() - 2);
  const double t = f - k;
  const Section &a = this->Sections[k], &b = this->Sections[k + 1];
  return {a.U0 + t * (b.U0 - a.U0), a.U1 + t * (b.U1 - a.U1), a.V0 + t * (b.V0 - a.V0), a.V1 + t * (b.V1 - a.V1)};
}

// The skin (inset 0) or the muscles' outline (inset = skin + fat) as a superellipse around the
// bones' cross-section widened by the soft-tissue margins.
double KneeSurfaceModel::Envelope(const double ras[3], double inset(const Margins&, int side)) const {
  const Section s = this->SectionAt(ras[2]);
  const Margins m = MarginsAt(ras[2]);
  const double lateral = s.U1 + m.Lateral - inset(kFat, 0), medial = s.U0 - m.Medial + inset(kFat, 1);
  const double anterior = s.V1 + m.Anterior - inset(kFat, 2), posterior = s.V0 - m.Posterior + inset(kFat, 3);
  double u, v;
  this->ToKneeAxes(ras, u, v);
  return Superellipse(u - 0.5 * (lateral + medial), v - 0.5 * (anterior + posterior), 0.5 * (lateral - medial),
                      0.5 * (anterior - posterior), kSuperellipse);
}

double KneeSurfaceModel::FatPads(const double ras[3]) const {
  double u, v;
  this->ToKneeAxes(ras, u, v);
  const double q[3] = {u, v, ras[2]};
  double best = kFarMm;
  for (const Pad& pad : this->Pads) {
    // First-order ellipsoid distance (exact on the surface).
    double k0 = 0, k1 = 0;
    for (int a = 0; a < 3; ++a) {
      const double x = q[a] - pad.Centre[a];
      k0 += (x / pad.Radii[a]) * (x / pad.Radii[a]);
      k1 += (x / (pad.Radii[a] * pad.Radii[a])) * (x / (pad.Radii[a] * pad.Radii[a]));
    }
    k0 = std::sqrt(k0);
    k1 = std::sqrt(k1);
    best = std::min(best, k1 < 1e-12 ? -std::min({pad.Radii[0], pad.Radii[1], pad.Radii[2]}) : k0 * (k0 - 1.0) / k1);
  }
  return best;
}

double KneeSurfaceModel::SignedDistance(KneeStructure structure, const double ras[3]) const {
  switch (structure) {
    case KneeStructure::FemurMarrow:
    case KneeStructure::TibiaMarrow:
    case KneeStructure::FibulaMarrow:
    case KneeStructure::PatellaMarrow: {
      const KneeStructure bone = static_cast<KneeStructure>(static_cast<int>(structure) - 4);
      return this->SignedDistance(bone, ras) + this->CorticalThickness(bone, ras);
    }
    case KneeStructure::Body:
      return this->Envelope(ras, [](const Margins&, int) { return 0.0; });
    case KneeStructure::MuscleCompartment:
      return this->Envelope(ras, [](const Margins& fat, int side) {
        const double perSide[4] = {fat.Lateral, fat.Medial, fat.Anterior, fat.Posterior};
        return KneeSkinMm + perSide[side];
      });
    case KneeStructure::FatPads:  // under the subcutaneous fat, between the muscles
      return std::max(this->FatPads(ras), this->SignedDistance(KneeStructure::MuscleCompartment, ras));
    default:
      break;
  }
  const Part* part = this->PartOf(structure);
  return part ? part->Distance.SignedDistance({ras[0], ras[1], ras[2]}) : kFarMm;
}

void KneeSurfaceModel::Bounds(KneeStructure structure, double bounds[6]) const {
  if (structure == KneeStructure::Body || structure == KneeStructure::MuscleCompartment) {
    const double b[6] = {-kFarMm, kFarMm, -kFarMm, kFarMm, -kFarMm, kFarMm};
    std::copy(b, b + 6, bounds);
    return;
  }
  if (structure == KneeStructure::FatPads) {
    // The pads' boxes in (u, v, z), turned into x, y: the radius of the (u, v) box bounds both.
    double b[6] = {kFarMm, -kFarMm, kFarMm, -kFarMm, kFarMm, -kFarMm};
    for (const Pad& pad : this->Pads) {
      const double x = pad.Centre[0] * this->AxisU[0] + pad.Centre[1] * this->AxisV[0];
      const double y = pad.Centre[0] * this->AxisU[1] + pad.Centre[1] * this->AxisV[1];
      const double r = std::hypot(pad.Radii[0], pad.Radii[1]);
      b[0] = std::min(b[0], x - r), b[1] = std::max(b[1], x + r);
      b[2] = std::min(b[2], y - r), b[3] = std::max(b[3], y + r);
      b[4] = std::min(b[4], pad.Centre[2] - pad.Radii[2]), b[5] = std::max(b[5], pad.Centre[2] + pad.Radii[2]);
    }
    std::copy(b, b + 6, bounds);
    return;
  }
  KneeStructure s = structure;
  if (s == KneeStructure::FemurMarrow || s == KneeStructure::TibiaMarrow || s == KneeStructure::FibulaMarrow ||
      s == KneeStructure::PatellaMarrow) {
    s = static_cast<KneeStructure>(static_cast<int>(s) - 4);
  }
  const Part* part = this->PartOf(s);
  if (!part) {
    std::fill(bounds, bounds + 6, 0.0);
    return;
  }
  const Vec3 &lo = part->Distance.Lo(), &hi = part->Distance.Hi();
  const double b[6] = {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
  std::copy(b, b + 6, bounds);
}

// The middle of the leg's extent (x, y) over 80 mm above and below the joint line.
void KneeSurfaceModel::FieldOfViewCentre(double ras[3]) const {
  double lo[2] = {kFarMm, kFarMm}, hi[2] = {-kFarMm, -kFarMm};
  for (double z = -80; z <= 80; z += 4) {
    const Section s = this->SectionAt(z);
    const Margins m = MarginsAt(z);
    const double lateral = s.U1 + m.Lateral, medial = s.U0 - m.Medial;
    const double anterior = s.V1 + m.Anterior, posterior = s.V0 - m.Posterior;
    const double a = 0.5 * (lateral - medial), b = 0.5 * (anterior - posterior);
    for (int step = 0; step < 72; ++step) {
      // A point of the superellipse at this angle.
      const double t = step * (2 * M_PI / 72), c = std::cos(t), sn = std::sin(t);
      const double u = 0.5 * (lateral + medial) + a * std::copysign(std::pow(std::abs(c), 2.0 / kSuperellipse), c);
      const double v = 0.5 * (anterior + posterior) + b * std::copysign(std::pow(std::abs(sn), 2.0 / kSuperellipse), sn);
      const double xy[2] = {u * this->AxisU[0] + v * this->AxisV[0], u * this->AxisU[1] + v * this->AxisV[1]};
      for (int r = 0; r < 2; ++r) lo[r] = std::min(lo[r], xy[r]), hi[r] = std::max(hi[r], xy[r]);
    }
  }
  ras[0] = 0.5 * (lo[0] + hi[0]);
  ras[1] = 0.5 * (lo[1] + hi[1]);
  ras[2] = 0.0;
}

double KneeSurfaceModel::CorticalThickness(KneeStructure bone, const double ras[3]) const {
  // Distance from the joint line along the leg (the patella has no diaphysis).
  const double along = SmoothStep(30.0, 110.0, std::abs(ras[2]));
  switch (bone) {
    case KneeStructure::Femur: return kFemurCortex.Epiphysis + along * (kFemurCortex.Diaphysis - kFemurCortex.Epiphysis);
    case KneeStructure::Tibia: return kTibiaCortex.Epiphysis + along * (kTibiaCortex.Diaphysis - kTibiaCortex.Epiphysis);
    case KneeStructure::Fibula:
      return kFibulaCortex.Epiphysis + along * (kFibulaCortex.Diaphysis - kFibulaCortex.Epiphysis);
    default: return kPatellaCortex;
  }
}

std::vector<std::array<double, 3>> KneeSurfaceModel::SurfacePoints(KneeStructure structure, int count,
                                                                   const double* boundsRAS) const {
  const Part* part = this->PartOf(structure);
  if (!part) return KneeModel::SurfacePoints(structure, count, boundsRAS);
  // Area-weighted samples on the triangles, deterministic.
  std::vector<std::array<double, 3>> points;
  if (count <= 0) return points;
  const TriangleMesh& mesh = part->Distance.Mesh();
  std::mt19937 rng(12345u + static_cast<unsigned>(structure));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double total = part->CumulativeArea.back();
  const long maxTries = 200L * count + 10000L;
  for (long tries = 0; tries < maxTries && static_cast<int>(points.size()) < count; ++tries) {
    const double at = unit(rng) * total;
    const size_t t = std::min(mesh.Triangles.size() - 1,
                              size_t(std::lower_bound(part->CumulativeArea.begin(), part->CumulativeArea.end(), at) -
                                     part->CumulativeArea.begin()));
    double a = unit(rng), b = unit(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const auto& tri = mesh.Triangles[t];
    const Vec3 p = mesh.Points[tri[0]] + (mesh.Points[tri[1]] - mesh.Points[tri[0]]) * a +
                   (mesh.Points[tri[2]] - mesh.Points[tri[0]]) * b;
    if (boundsRAS && (p.x < boundsRAS[0] || p.x > boundsRAS[1] || p.y < boundsRAS[2] || p.y > boundsRAS[3] ||
                      p.z < boundsRAS[4] || p.z > boundsRAS[5]))
      continue;
    points.push_back({p.x, p.y, p.z});
  }
  return points;
}

vtkSmartPointer<vtkPolyData> KneeSurfaceModel::Surface(KneeStructure structure) const {
  const Part* part = this->PartOf(structure);
  return part ? part->Poly : nullptr;
}

// Mesh structures: the exact distance in a band around the surface (bounded BVH queries, most
// voxels of a box are far from the surface and cheap), the sign elsewhere by flooding from the
// band: a region of far voxels is bounded by band voxels of one sign only, because the band is
// wider than a voxel step.
void KneeSurfaceModel::SampleSignedDistance(KneeStructure structure, const KneeGrid& grid, const KneeGridBox& box,
                                            double band, float* out) const {
  const Part* part = this->PartOf(structure);
  if (!part) {
    KneeModel::SampleSignedDistance(structure, grid, box, band, out);
    return;
  }
  const double step = std::max({grid.Spacing[0], grid.Spacing[1], grid.Spacing[2]});
  band = std::max(band, 1.5 * step);
  const int nx = box.Hi[0] - box.Lo[0], ny = box.Hi[1] - box.Lo[1], nz = box.Hi[2] - box.Lo[2];
  const size_t n = box.Size();
  if (n == 0) return;
  const float unknown = std::numeric_limits<float>::quiet_NaN();
  std::vector<uint32_t> queue;
  queue.reserve(n / 4);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double p[3];
        grid.VoxelCentre(box.Lo[0] + i, box.Lo[1] + j, box.Lo[2] + k, p);
        double d;
        const size_t at = (size_t(k) * ny + j) * nx + i;
        if (part->Distance.SignedDistance({p[0], p[1], p[2]}, band, d)) {
          out[at] = static_cast<float>(d);
          queue.push_back(static_cast<uint32_t>(at));
        } else {
          out[at] = unknown;
        }
      }
  if (queue.empty()) {
    double p[3];
    grid.VoxelCentre((box.Lo[0] + box.Hi[0]) / 2, (box.Lo[1] + box.Hi[1]) / 2, (box.Lo[2] + box.Hi[2]) / 2, p);
    const float far = static_cast<float>(part->Distance.SignedDistance({p[0], p[1], p[2]}) < 0 ? -2 * band : 2 * band);
    std::fill(out, out + n, far);
    return;
  }
  const float farInside = static_cast<float>(-2 * band), farOutside = static_cast<float>(2 * band);
  for (size_t head = 0; head < queue.size(); ++head) {
    const uint32_t at = queue[head];
    const float value = out[at] < 0 ? farInside : farOutside;
    const int i = static_cast<int>(at % nx), j = static_cast<int>((at / nx) % ny), k = static_cast<int>(at / (size_t(nx) * ny));
    const int neighbours[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
    for (const auto& q : neighbours) {
      if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= nx || q[1] >= ny || q[2] >= nz) continue;
      const size_t next = (size_t(q[2]) * ny + q[1]) * nx + q[0];
      if (!std::isnan(out[next])) continue;
      out[next] = value;
      queue.push_back(static_cast<uint32_t>(next));
    }
  }
}

}  // namespace

std::shared_ptr<const KneeModel> LoadKneeSurfaceModel(std::string& error) {
  // Loaded once per process: the surfaces and their distance trees are shared by every phantom.
  // (per resources folder: a test may point ROBOPLAN_RESOURCES_DIR elsewhere).
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const KneeModel>> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  const std::string folder = ResourcePath("Anatomy/KneeVHF");
  auto& model = loaded[folder];
  if (!model) {
    auto fresh = std::make_shared<KneeSurfaceModel>();
    if (!fresh->Load(folder, error)) return nullptr;
    model = fresh;
  }
  return model;
}

}  // namespace rp
