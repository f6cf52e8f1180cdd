// The knee phantom's renderer: whichever anatomy (real surfaces or analytic solids), the
// labelmap, the CT and the MR follow from the structures' signed distances by one rule, the
// tissue layers below (top first). A voxel's value composites the layers by their coverage of
// the voxel (partial volume from the signed distance and the voxel's extent along the surface
// normal), then scanner noise is added. The volume is rendered in slabs of slices on two threads.
#include "rpKneePhantom.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

#include <vtkPolyData.h>
#include <vtkTransform.h>

namespace rp {
namespace {


// The tissue layers, top first: a point gets the label of the first layer it is inside.
// Cartilage is painted over bone (the real cartilages overlap the bones by a few tenths of a
// millimetre), the trabecular core over the cortex, bones over ligaments (which end on them).
struct Layer {
  KneeStructure Structure;
  double Offset;  // the layer's surface: signed distance of the structure + Offset = 0
  KneeLabel Label;
};
const Layer kLayers[] = {
    {KneeStructure::FemoralCartilage, 0, KneeFemoralCartilage},
    {KneeStructure::TibialCartilage, 0, KneeTibialCartilage},
    {KneeStructure::PatellarCartilage, 0, KneePatellarCartilage},
    {KneeStructure::PatellaMarrow, 0, KneePatellaTrabecular},
    {KneeStructure::Patella, 0, KneePatellaCortical},
    {KneeStructure::FemurMarrow, 0, KneeFemurTrabecular},
    {KneeStructure::Femur, 0, KneeFemurCortical},
    {KneeStructure::TibiaMarrow, 0, KneeTibiaTrabecular},
    {KneeStructure::Tibia, 0, KneeTibiaCortical},
    {KneeStructure::FibulaMarrow, 0, KneeFibulaTrabecular},
    {KneeStructure::Fibula, 0, KneeFibulaCortical},
    {KneeStructure::ACL, 0, KneeACL},
    {KneeStructure::PCL, 0, KneePCL},
    {KneeStructure::MCL, 0, KneeMCL},
    {KneeStructure::LCL, 0, KneeLCL},
    {KneeStructure::FatPads, 0, KneeFat},
    {KneeStructure::MuscleCompartment, 0, KneeMuscle},
    {KneeStructure::Body, KneeSkinMm, KneeFat},  // subcutaneous fat: inside the skin
    {KneeStructure::Body, 0, KneeSkin},
};
constexpr int kLayerCount = sizeof(kLayers) / sizeof(kLayers[0]);

bool IsMarrow(KneeStructure s) {
  return s == KneeStructure::FemurMarrow || s == KneeStructure::TibiaMarrow || s == KneeStructure::FibulaMarrow ||
         s == KneeStructure::PatellaMarrow;
}
KneeStructure BoneOfMarrow(KneeStructure s) { return static_cast<KneeStructure>(static_cast<int>(s) - 4); }
bool IsTrabecular(KneeLabel l) {
  return l == KneeFemurTrabecular || l == KneeTibiaTrabecular || l == KneeFibulaTrabecular || l == KneePatellaTrabecular;
}

// ---- Tissue texture and density (real anatomy only)

// Smooth value noise in [-1, 1] on a lattice of `cell` mm: a deterministic function of the
// anatomical position, so the CT and the MR (in another pose) see the same trabeculae.
double ValueNoise(const double p[3], double cell, uint32_t seed) {
  double f[3];
  long c[3];
  for (int a = 0; a < 3; ++a) {
    const double x = p[a] / cell;
    c[a] = static_cast<long>(std::floor(x));
    const double t = x - c[a];
    f[a] = t * t * (3 - 2 * t);
  }
  auto hash = [seed](long i, long j, long k) {
    uint32_t h = seed ^ (static_cast<uint32_t>(i) * 73856093u) ^ (static_cast<uint32_t>(j) * 19349663u) ^
                 (static_cast<uint32_t>(k) * 83492791u);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 0xffff) / 32767.5 - 1.0;
  };
  double v = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
    const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
    v += w * hash(c[0] + di, c[1] + dj, c[2] + dk);
  }
  return v;
}
double Trabeculae(const double p[3]) { return 0.65 * ValueNoise(p, 1.3, 0x9e3779b9u) + 0.35 * ValueNoise(p, 0.6, 0x7f4a7c15u); }

// Trabecular bone is densest under the joint (epiphysis, ~300 HU) and thins out along the
// metaphysis into the fatty marrow of the diaphysis (calibrated on the Visible Human Female's
// knee CT, ../shared/data/knee-ct-vhf: ~250 HU under the plateau, ~80 HU 60-100 mm below it).
double TrabecularCT(double epiphysisHU, const double p[3]) {
  const double s = std::abs(p[2]);
  const double metaphysis = std::clamp((s - 20.0) / 50.0, 0.0, 1.0);
  const double diaphysis = std::clamp((s - 75.0) / 40.0, 0.0, 1.0);
  const double base = epiphysisHU - 90.0 * metaphysis;
  return base + diaphysis * (20.0 - base) + 80.0 * (1.0 - 0.6 * diaphysis) * Trabeculae(p);
}

// ---- Grid helpers

vtkSmartPointer<vtkMatrix4x4> MatrixOf(const KneeGrid& g) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m->SetElement(r, c, g.Axes[c][r] * g.Spacing[c]);
    m->SetElement(c, 3, g.Origin[c]);
  }
  return m;
}

void CentreGrid(KneeGrid& g, const double centre[3]) {
  for (int r = 0; r < 3; ++r) {
    g.Origin[r] = centre[r];
    for (int c = 0; c < 3; ++c) g.Origin[r] -= g.Axes[c][r] * g.Spacing[c] * (g.Dims[c] - 1) * 0.5;
  }
}

// Allocates a volume on a grid and returns its voxels.
template <typename T>
T* Allocate(ImageVolume& volume, const KneeGrid& g, int scalarType, double window, double level,
            const std::string& modality, const std::string& description) {
  volume.Image = vtkSmartPointer<vtkImageData>::New();
  volume.Image->SetDimensions(g.Dims[0], g.Dims[1], g.Dims[2]);
  volume.Image->AllocateScalars(scalarType, 1);
  volume.IJKToRAS = MatrixOf(g);
  volume.Window = window;
  volume.Level = level;
  volume.Modality = modality;
  volume.Description = description;
  return static_cast<T*>(volume.Image->GetScalarPointer());
}

// The voxels of `slab` (a range of k) whose centres lie within `margin` of an RAS box.
KneeGridBox BoxAround(const KneeGrid& g, const double bounds[6], double margin, const KneeGridBox& slab) {
  KneeGridBox box = slab;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const double p[3] = {(corner & 1 ? bounds[1] + margin : bounds[0] - margin),
                         (corner & 2 ? bounds[3] + margin : bounds[2] - margin),
                         (corner & 4 ? bounds[5] + margin : bounds[4] - margin)};
    for (int c = 0; c < 3; ++c) {
      // Index along axis c (the axes are orthonormal).
      double x = 0;
      for (int r = 0; r < 3; ++r) x += (p[r] - g.Origin[r]) * g.Axes[c][r];
      x /= g.Spacing[c];
      lo[c] = std::min(lo[c], x);
      hi[c] = std::max(hi[c], x);
    }
  }
  for (int c = 0; c < 3; ++c) {
    box.Lo[c] = std::max(slab.Lo[c], static_cast<int>(std::max(-1e9, std::floor(lo[c]))));
    box.Hi[c] = std::min(slab.Hi[c], static_cast<int>(std::min(1e9, std::ceil(hi[c]))) + 1);
  }
  return box;
}

// One structure's signed distances over a box of the current slab.
struct Sampled {
  KneeGridBox Box;
  std::vector<float> D;
  float Far = 1e9f;  // value outside the box (outside the structure)
  float At(int i, int j, int k) const {
    if (i < Box.Lo[0] || j < Box.Lo[1] || k < Box.Lo[2] || i >= Box.Hi[0] || j >= Box.Hi[1] || k >= Box.Hi[2]) return Far;
    const int nx = Box.Hi[0] - Box.Lo[0], ny = Box.Hi[1] - Box.Lo[1];
    return D[(size_t(k - Box.Lo[2]) * ny + (j - Box.Lo[1])) * nx + (i - Box.Lo[0])];
  }
  // Gradient (per mm along the grid axes) by central differences inside the box.
  void Gradient(int i, int j, int k, const double spacing[3], double g[3]) const {
    const int idx[3] = {i, j, k};
    for (int c = 0; c < 3; ++c) {
      int a[3] = {i, j, k}, b[3] = {i, j, k};
      a[c] = std::max(Box.Lo[c], idx[c] - 1);
      b[c] = std::min(Box.Hi[c] - 1, idx[c] + 1);
      g[c] = b[c] > a[c] ? (At(b[0], b[1], b[2]) - At(a[0], a[1], a[2])) / ((b[c] - a[c]) * spacing[c]) : 0.0;
    }
  }
};

// What a layer shows in an image, per tissue, and the scanner's per-voxel effects.
struct Modality {
  bool CT;
  bool Realistic;  // texture and density gradients (real anatomy)
  double Value(KneeLabel label, const double p[3]) const {
    const KneeTissue& t = KneeTissues()[label];
    if (!this->CT) {
      // Fatty marrow is bright on PD; the trabeculae darken it a little.
      return t.MRIntensity - (this->Realistic && IsTrabecular(label) ? 70.0 * Trabeculae(p) : 0.0);
    }
    if (this->Realistic && IsTrabecular(label)) return TrabecularCT(t.CTHounsfield, p);
    return t.CTHounsfield;
  }
};

// Renders slices [k0, k1) of one grid: labels (optional) and intensities (optional).
struct SlabRenderer {
  const KneeModel& Model;
  const KneeGrid& Grid;
  const Modality* Image;     // null: labels only
  unsigned char* LabelsOut;  // null: no labels
  double* ValuesOut;         // k0..k1 slices of values before noise (null with Image null)

  void Render(int k0, int k1) {
    const KneeGridBox slab{{0, 0, k0}, {Grid.Dims[0], Grid.Dims[1], k1}};
    // The partial-volume ramp: a layer covers a voxel fully (or not at all) beyond half the
    // voxel's diagonal from its surface.
    const double halfDiagonal =
        0.5 * std::sqrt(Grid.Spacing[0] * Grid.Spacing[0] + Grid.Spacing[1] * Grid.Spacing[1] +
                        Grid.Spacing[2] * Grid.Spacing[2]);
    const double step = std::max({Grid.Spacing[0], Grid.Spacing[1], Grid.Spacing[2]});
    Sampled sampled[KneeStructureCount];
    for (int s = 0; s < KneeStructureCount; ++s) {
      const KneeStructure structure = static_cast<KneeStructure>(s);
      if (IsMarrow(structure)) continue;  // from its bone's distance and the cortical thickness
      const bool bone = s <= static_cast<int>(KneeStructure::Patella);
      // Exact distances where a layer surface may cross a voxel: the bone's cortex reaches its
      // thickness inside; the skin's inner surface is KneeSkinMm inside the body.
      const double band = halfDiagonal + step + (bone ? Model.MaxCorticalThickness() : 0.0) +
                          (structure == KneeStructure::Body ? KneeSkinMm : 0.0);
      double bounds[6];
      Model.Bounds(structure, bounds);
      Sampled& out = sampled[s];
      out.Box = BoxAround(Grid, bounds, band + step, slab);
      out.Far = static_cast<float>(2 * band + 1);
      out.D.resize(out.Box.Size());
      if (!out.Box.Empty()) Model.SampleSignedDistance(structure, Grid, out.Box, band, out.D.data());
    }
    double distances[kLayerCount];
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < Grid.Dims[1]; ++j)
        for (int i = 0; i < Grid.Dims[0]; ++i) {
          double p[3];
          Grid.VoxelCentre(i, j, k, p);
          // Layer distances (marrow: the bone's distance + the cortex there).
          for (int l = 0; l < kLayerCount; ++l) {
            const KneeStructure s = kLayers[l].Structure;
            if (IsMarrow(s)) {
              const double bone = sampled[static_cast<int>(BoneOfMarrow(s))].At(i, j, k);
              distances[l] = bone < halfDiagonal ? bone + Model.CorticalThickness(BoneOfMarrow(s), p) : bone;
            } else {
              distances[l] = sampled[static_cast<int>(s)].At(i, j, k) + kLayers[l].Offset;
            }
          }
          const size_t at = (size_t(k - k0) * Grid.Dims[1] + j) * Grid.Dims[0] + i;
          if (LabelsOut) {
            KneeLabel label = KneeBackground;
            for (int l = 0; l < kLayerCount; ++l)
              if (distances[l] < 0) {
                label = kLayers[l].Label;
                break;
              }
            LabelsOut[at] = label;
          }
          if (!Image) continue;
          // Composite the layers top-down by coverage; air fills what is left.
          double value = 0, remaining = 1;
          for (int l = 0; l < kLayerCount && remaining > 1e-6; ++l) {
            const double d = distances[l];
            if (d >= halfDiagonal) continue;
            double coverage = 1.0;
            if (d > -halfDiagonal) {
              const KneeStructure s = IsMarrow(kLayers[l].Structure) ? BoneOfMarrow(kLayers[l].Structure)
                                                                     : kLayers[l].Structure;
              double g[3];
              sampled[static_cast<int>(s)].Gradient(i, j, k, Grid.Spacing, g);
              const double norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
              double width = std::cbrt(Grid.Spacing[0] * Grid.Spacing[1] * Grid.Spacing[2]);
              if (norm > 1e-6) {
                width = 0;
                for (int c = 0; c < 3; ++c) width += (g[c] / norm * Grid.Spacing[c]) * (g[c] / norm * Grid.Spacing[c]);
                width = std::sqrt(width);
              }
              coverage = std::clamp(0.5 - d / width, 0.0, 1.0);
            }
            if (coverage <= 0) continue;
            value += remaining * coverage * Image->Value(kLayers[l].Label, p);
            remaining *= 1.0 - coverage;
          }
          ValuesOut[at] = value + remaining * Image->Value(KneeBackground, p);
        }
  }
};

// Renders a whole grid in slabs on two threads; `write(k0, k1, labels, values)` stores a slab.
template <typename WriteFn>
void RenderGrid(const KneeModel& model, const KneeGrid& grid, const Modality* image, bool labels, WriteFn write,
                const ProgressCallback& progress, double from, double to, const std::string& message) {
  const int slabSize = 8;
  const int slabs = (grid.Dims[2] + slabSize - 1) / slabSize;
  std::atomic<int> next{0}, done{0};
  auto worker = [&](bool reports) {
    std::vector<unsigned char> labelBuffer;
    std::vector<double> valueBuffer;
    for (int s = next++; s < slabs; s = next++) {
      const int k0 = s * slabSize, k1 = std::min(grid.Dims[2], k0 + slabSize);
      const size_t n = size_t(k1 - k0) * grid.Dims[0] * grid.Dims[1];
      labelBuffer.resize(labels ? n : 0);
      valueBuffer.resize(image ? n : 0);
      SlabRenderer renderer{model, grid, image, labels ? labelBuffer.data() : nullptr,
                            image ? valueBuffer.data() : nullptr};
      renderer.Render(k0, k1);
      write(k0, k1, labels ? labelBuffer.data() : nullptr, image ? valueBuffer.data() : nullptr);
      ++done;
      if (reports && progress) progress(from + (to - from) * done.load() / slabs, message);
    }
  };
  const unsigned hw = std::max(1u, std::min(2u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < hw; ++t) threads.emplace_back(worker, false);
  worker(true);
  for (auto& t : threads) t.join();
  if (progress) progress(to, message);
}

}  // namespace

// ---- Tissues and bones

const std::vector<KneeTissue>& KneeTissues() {
  // CT values as measured on real knees (fat -100, muscle +50, cortical bone ~1400 HU; the
  // trabecular value is the epiphysis', see TrabecularCT); PD-MR: fat and fatty marrow bright,
  // cortex and ligaments dark, cartilage intermediate-bright.
  static const std::vector<KneeTissue> tissues = {
      {KneeBackground, "air", "", -1000, 0, {0, 0, 0}},
      {KneeSkin, "skin", "skin", 30, 450, {0.95, 0.78, 0.66}},
      {KneeFat, "fat", "fat", -100, 900, {0.98, 0.9, 0.55}},
      {KneeMuscle, "muscle", "muscle", 50, 350, {0.75, 0.3, 0.25}},
      {KneeFemurCortical, "femur cortical", "bone", 1400, 40, {0.95, 0.93, 0.85}},
      {KneeFemurTrabecular, "femur trabecular", "bone", 300, 720, {0.9, 0.82, 0.65}},
      {KneeTibiaCortical, "tibia cortical", "bone", 1400, 40, {0.95, 0.93, 0.85}},
      {KneeTibiaTrabecular, "tibia trabecular", "bone", 300, 720, {0.9, 0.82, 0.65}},
      {KneeFibulaCortical, "fibula cortical", "bone", 1350, 40, {0.95, 0.93, 0.85}},
      {KneeFibulaTrabecular, "fibula trabecular", "bone", 280, 720, {0.9, 0.82, 0.65}},
      {KneePatellaCortical, "patella cortical", "bone", 1300, 40, {0.95, 0.93, 0.85}},
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

const char* KneeStructureName(KneeStructure structure) {
  static const char* const names[KneeStructureCount] = {
      "femur", "tibia", "fibula", "patella", "femur-marrow", "tibia-marrow", "fibula-marrow", "patella-marrow",
      "femoral-cartilage", "tibial-cartilage", "patellar-cartilage", "acl", "pcl", "mcl", "lcl", "body",
      "muscle-compartment", "fat-pads"};
  const int s = static_cast<int>(structure);
  return s >= 0 && s < KneeStructureCount ? names[s] : "unknown";
}

const std::array<KneeBone, 4>& KneeBones() {
  static const std::array<KneeBone, 4> bones = {{
      {"femur", "Femur", KneeStructure::Femur, KneeStructure::FemurMarrow, KneeFemurCortical, KneeFemurTrabecular,
       {0.95, 0.84, 0.57}},
      {"tibia", "Tibia", KneeStructure::Tibia, KneeStructure::TibiaMarrow, KneeTibiaCortical, KneeTibiaTrabecular,
       {0.60, 0.78, 0.95}},
      {"fibula", "Fibula", KneeStructure::Fibula, KneeStructure::FibulaMarrow, KneeFibulaCortical, KneeFibulaTrabecular,
       {0.62, 0.86, 0.58}},
      {"patella", "Patella", KneeStructure::Patella, KneeStructure::PatellaMarrow, KneePatellaCortical,
       KneePatellaTrabecular, {0.96, 0.62, 0.48}},
  }};
  return bones;
}

void KneeGrid::VoxelCentre(int i, int j, int k, double ras[3]) const {
  for (int r = 0; r < 3; ++r)
    ras[r] = this->Origin[r] + this->Axes[0][r] * this->Spacing[0] * i + this->Axes[1][r] * this->Spacing[1] * j +
             this->Axes[2][r] * this->Spacing[2] * k;
}

// ---- KneeModel defaults

KneeLabel KneeModel::LabelAt(const double ras[3]) const {
  for (const Layer& layer : kLayers) {
    // Outside a structure's box its distance is positive (and every offset is >= 0).
    double b[6];
    this->Bounds(layer.Structure, b);
    if (ras[0] < b[0] || ras[0] > b[1] || ras[1] < b[2] || ras[1] > b[3] || ras[2] < b[4] || ras[2] > b[5]) continue;
    if (this->SignedDistance(layer.Structure, ras) + layer.Offset < 0.0) return layer.Label;
  }
  return KneeBackground;
}

std::vector<std::array<double, 3>> KneeModel::SurfacePoints(KneeStructure structure, int count,
                                                            const double* boundsRAS) const {
  // Uniform samples in a thin shell around the surface (roughly uniform on it), projected onto
  // it by Newton steps along the numerical gradient. Long structures are cut at |z| = 160 mm.
  std::vector<std::array<double, 3>> points;
  if (count <= 0) return points;
  double box[6];
  this->Bounds(structure, box);
  box[4] = std::max(box[4], -160.0);
  box[5] = std::min(box[5], 160.0);
  for (int a = 0; a < 3; ++a) {
    box[2 * a] = std::max(box[2 * a], -1000.0);
    box[2 * a + 1] = std::min(box[2 * a + 1], 1000.0);
    if (boundsRAS) {
      box[2 * a] = std::max(box[2 * a], boundsRAS[2 * a]);
      box[2 * a + 1] = std::min(box[2 * a + 1], boundsRAS[2 * a + 1]);
    }
    if (box[2 * a] >= box[2 * a + 1]) return points;
  }
  std::mt19937 rng(12345u + static_cast<unsigned>(structure));
  std::uniform_real_distribution<double> ux(box[0], box[1]), uy(box[2], box[3]), uz(box[4], box[5]);
  const double band = 1.0;
  points.reserve(count);
  const long maxTries = 4000L * count + 100000L;
  for (long tries = 0; tries < maxTries && static_cast<int>(points.size()) < count; ++tries) {
    double p[3] = {ux(rng), uy(rng), uz(rng)};
    if (std::abs(this->SignedDistance(structure, p)) > band) continue;
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
    for (int a = 0; a < 3; ++a) inBox = inBox && p[a] >= box[2 * a] && p[a] <= box[2 * a + 1];
    if (inBox) points.push_back({p[0], p[1], p[2]});
  }
  return points;
}

vtkSmartPointer<vtkPolyData> KneeModel::Surface(KneeStructure) const { return nullptr; }

void KneeModel::SampleSignedDistance(KneeStructure structure, const KneeGrid& grid, const KneeGridBox& box, double,
                                     float* out) const {
  for (int k = box.Lo[2]; k < box.Hi[2]; ++k)
    for (int j = box.Lo[1]; j < box.Hi[1]; ++j)
      for (int i = box.Lo[0]; i < box.Hi[0]; ++i) {
        double p[3];
        grid.VoxelCentre(i, j, k, p);
        *out++ = static_cast<float>(this->SignedDistance(structure, p));
      }
}

// ---- The phantom

namespace {

void SetGrid(KneeGrid& g, std::array<int, 3> dims, std::array<double, 3> spacing) {
  for (int a = 0; a < 3; ++a) g.Dims[a] = dims[a], g.Spacing[a] = spacing[a];
}

// The CT and MR grids' sizes and spacings: the preset of options.Size, or the CT's explicit grid.
bool SizeGrids(const KneePhantomOptions& options, KneeGrid& ct, KneeGrid& mr, std::string& error) {
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
    }
    SetGrid(ct, options.CTDimensions, options.CTSpacing);
  }
  switch (options.Size) {
    case KneePhantomSize::Small:
      if (!explicitGrid) SetGrid(ct, {110, 110, 64}, {1.6, 1.6, 2.5});
      SetGrid(mr, {96, 96, 84}, {1.6, 1.6, 1.7});
      break;
    case KneePhantomSize::Demo:
      if (!explicitGrid) SetGrid(ct, {220, 220, 128}, {0.8, 0.8, 1.25});
      SetGrid(mr, {192, 192, 84}, {0.8, 0.8, 1.7});
      break;
    case KneePhantomSize::Full:
      if (!explicitGrid) SetGrid(ct, {512, 512, 300}, {0.34, 0.34, 1.0});
      SetGrid(mr, {384, 384, 90}, {0.4, 0.4, 1.7});
      break;
  }
  return true;
}

// Orients and centres both grids on the knee and sets the phantom's true CT-to-MR pose.
void PlaceGrids(const KneeModel& model, const KneePhantomOptions& options, KneeGrid& ct, KneeGrid& mr,
                KneePhantom& phantom) {
  // CT: axial, DICOM's usual LPS identity directions → RAS i = -x, j = -y, k = +z.
  const double ctAxes[3][3] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
  std::copy(&ctAxes[0][0], &ctAxes[0][0] + 9, &ct.Axes[0][0]);
  double centre[3];
  model.FieldOfViewCentre(centre);
  CentreGrid(ct, centre);
  vtkNew<vtkTransform> pose;
  pose->PostMultiply();
  pose->RotateX(options.MRRotationDegrees[0]);
  pose->RotateY(options.MRRotationDegrees[1]);
  pose->RotateZ(options.MRRotationDegrees[2]);
  pose->Translate(options.MRTranslation[0], options.MRTranslation[1], options.MRTranslation[2]);
  phantom.CTToMR->DeepCopy(pose->GetMatrix());

  // MR: sagittal proton density, 1.7 mm slices. LPS IOP (0,1,0 / 0,0,-1) → RAS i = -y,
  // j = -z, slice normal k = +x. Centred on the knee where the MR sees it, a little off (an
  // MR isocentre is not a CT's).
  const double mrAxes[3][3] = {{0, -1, 0}, {0, 0, -1}, {1, 0, 0}};
  std::copy(&mrAxes[0][0], &mrAxes[0][0] + 9, &mr.Axes[0][0]);
  double mrCentre[4] = {centre[0], centre[1], centre[2], 1.0};
  phantom.CTToMR->MultiplyPoint(mrCentre, mrCentre);
  mrCentre[0] += 2.0, mrCentre[1] -= 3.0, mrCentre[2] += 4.0;
  CentreGrid(mr, mrCentre);
}

// CT and labels in one pass (the label is the rule at the voxel centre).
void RenderCTAndLabels(const KneeModel& model, const KneePhantomOptions& options, const KneeGrid& ct,
                       KneePhantom& phantom, const ProgressCallback& progress, double from, double to) {
  short* ctOut = nullptr;
  unsigned char* labelsOut = nullptr;
  if (options.GenerateLabels) {
    labelsOut = Allocate<unsigned char>(phantom.Labels, ct, VTK_UNSIGNED_CHAR, 0, 0, "SEG",
                                        "RoboPlan knee phantom ground truth");
  }
  const Modality ctModality{true, model.RealisticTissue()};
  if (options.GenerateCT) {
    ctOut = Allocate<short>(phantom.CT, ct, VTK_SHORT, 2000, 400, "CT", "RoboPlan knee phantom CT");
  }
  const size_t sliceSize = size_t(ct.Dims[0]) * ct.Dims[1];
  RenderGrid(
      model, ct, options.GenerateCT ? &ctModality : nullptr, options.GenerateLabels,
      [&](int k0, int k1, const unsigned char* labels, const double* values) {
        if (labels) std::copy(labels, labels + (k1 - k0) * sliceSize, labelsOut + k0 * sliceSize);
        if (!values) return;
        for (int k = k0; k < k1; ++k) {
          // Noise per slice from its own seed: identical output whatever the thread order.
          std::mt19937 rng(options.Seed * 2654435761u + 17u * static_cast<unsigned>(k) + 1u);
          std::normal_distribution<double> noise(0.0, options.CTNoiseHU);
          for (size_t n = 0; n < sliceSize; ++n) {
            double v = values[(k - k0) * sliceSize + n];
            if (v > -999.5) v += noise(rng);  // air stays at -1000 (below the scanner's noise floor)
            ctOut[k * sliceSize + n] = static_cast<short>(std::lround(std::clamp(v, -1024.0, 3071.0)));
          }
        }
      },
      progress, from, to, options.GenerateCT ? "CT" : "labels");
}

void RenderMR(const KneeModel& model, const KneePhantomOptions& options, const KneeGrid& mr, KneePhantom& phantom,
              const ProgressCallback& progress, double from, double to) {
  vtkNew<vtkMatrix4x4> mrToCT;
  vtkMatrix4x4::Invert(phantom.CTToMR, mrToCT);
  unsigned short* mrOut =
      Allocate<unsigned short>(phantom.MR, mr, VTK_UNSIGNED_SHORT, 1000, 500, "MR", "RoboPlan knee phantom PD");
  // The MR grid in anatomy (CT) coordinates: the knee moved by CTToMR.
  KneeGrid anatomy = mr;
  double o[4] = {mr.Origin[0], mr.Origin[1], mr.Origin[2], 1.0};
  mrToCT->MultiplyPoint(o, o);
  for (int r = 0; r < 3; ++r) anatomy.Origin[r] = o[r];
  for (int c = 0; c < 3; ++c) {
    double a[4] = {mr.Axes[c][0], mr.Axes[c][1], mr.Axes[c][2], 0.0};
    mrToCT->MultiplyPoint(a, a);
    for (int r = 0; r < 3; ++r) anatomy.Axes[c][r] = a[r];
  }
  const Modality mrModality{false, model.RealisticTissue()};
  const size_t sliceSize = size_t(mr.Dims[0]) * mr.Dims[1];
  RenderGrid(
      model, anatomy, &mrModality, false,
      [&](int k0, int k1, const unsigned char*, const double* values) {
        for (int k = k0; k < k1; ++k) {
          std::mt19937 rng(options.Seed * 2246822519u + 31u * static_cast<unsigned>(k) + 7u);
          std::normal_distribution<double> noise(0.0, options.MRNoise);
          for (int j = 0; j < mr.Dims[1]; ++j)
            for (int i = 0; i < mr.Dims[0]; ++i) {
              double p[3];
              anatomy.VoxelCentre(i, j, k, p);
              // A gentle receive-coil bias along the leg, as in a real knee coil.
              const double bias = 1.0 - 0.15 * std::min(1.0, std::abs(p[2]) / 120.0);
              const size_t n = size_t(j) * mr.Dims[0] + i;
              const double v = values[(k - k0) * sliceSize + n] * bias;
              // Rician magnitude noise: |signal + complex Gaussian|.
              const double re = v + noise(rng), im = noise(rng);
              mrOut[k * sliceSize + n] =
                  static_cast<unsigned short>(std::lround(std::min(std::sqrt(re * re + im * im), 65535.0)));
            }
        }
      },
      progress, from, to, "MR");
}

}  // namespace

bool GenerateKneePhantom(const KneePhantomOptions& options, KneePhantom& phantom, std::string& error,
                         const ProgressCallback& progress) {
  try {
    std::shared_ptr<const KneeModel> model;
    if (options.Anatomy == KneeAnatomy::Analytic) {
      model = std::make_shared<KneeAnalyticModel>();
    } else {
      model = LoadKneeSurfaceModel(error);
      if (!model) return false;
    }
    KneeGrid ct, mr;
    if (!SizeGrids(options, ct, mr, error)) return false;
    phantom.Model = model;
    PlaceGrids(*model, options, ct, mr, phantom);

    // Progress: one stage for CT and labels, one for MR.
    const bool renderCT = options.GenerateCT || options.GenerateLabels;
    const double stages = std::max((renderCT ? 1 : 0) + (options.GenerateMR ? 1 : 0), 1);
    if (renderCT) RenderCTAndLabels(*model, options, ct, phantom, progress, 0.0, 1.0 / stages);
    if (options.GenerateMR) RenderMR(*model, options, mr, phantom, progress, (renderCT ? 1.0 : 0.0) / stages, 1.0);
    return true;
  } catch (const std::bad_alloc&) {
    error = "knee phantom: out of memory";
  } catch (const std::exception& e) {
    error = std::string("knee phantom: ") + e.what();
  }
  return false;
}

}  // namespace rp
