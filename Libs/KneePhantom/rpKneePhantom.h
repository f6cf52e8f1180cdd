#pragma once
// The built-in knee phantom: a right knee (RAS, millimetres) rendered as a CT, a proton-density
// MR in another pose with 1.7 mm slices, and the ground-truth labelmap.
//
// Two anatomies, one renderer:
// - the real knee (default): the Visible Human Female's femur, tibia, fibula, patella, cartilages
//   and ligaments as closed surfaces (Resources/Anatomy/KneeVHF), with muscle, fat and skin
//   envelopes generated around them; the truth is those surfaces (KneeSurfaceModel);
// - analytic solids (capsules, ellipsoids, smooth unions) with closed-form distances, for tests
//   that need exact answers (KneeAnalyticModel).
//
// Anatomy frame (= CT RAS): the knee joint centre at the origin, +x lateral (a right knee: the
// patient's right), +y anterior (patella side), +z superior (femur above, tibia below).
// Every structure has a signed distance (negative inside, mm); the labelmap, the CT and the MR
// all follow from those distances by one rule (KneeModel::LabelAt).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpImageVolume.h"
#include "rpProgress.h"

class vtkPolyData;

namespace rp {

/// Label values of the ground-truth labelmap (unsigned char). 0 = air/background.
enum KneeLabel : unsigned char {
  KneeBackground = 0,
  KneeSkin = 1,
  KneeFat = 2,
  KneeMuscle = 3,
  KneeFemurCortical = 4,
  KneeFemurTrabecular = 5,
  KneeTibiaCortical = 6,
  KneeTibiaTrabecular = 7,
  KneeFibulaCortical = 8,
  KneeFibulaTrabecular = 9,
  KneePatellaCortical = 10,
  KneePatellaTrabecular = 11,
  KneeFemoralCartilage = 12,
  KneeTibialCartilage = 13,
  KneePatellarCartilage = 14,
  KneeACL = 15,
  KneePCL = 16,
  KneeMCL = 17,
  KneeLCL = 18,
  KneeLabelCount = 19
};

/// Structures with a surface (a bone = cortical + trabecular together).
enum class KneeStructure {
  Femur, Tibia, Fibula, Patella,                          // outer (periosteal) bone surfaces
  FemurMarrow, TibiaMarrow, FibulaMarrow, PatellaMarrow,  // trabecular cores (inside the cortex)
  FemoralCartilage, TibialCartilage, PatellarCartilage,
  ACL, PCL, MCL, LCL,
  Body,               // skin outer surface
  MuscleCompartment,  // the muscles' outer boundary (under the subcutaneous fat)
  FatPads             // popliteal and infrapatellar (Hoffa's) fat pads
};
constexpr int KneeStructureCount = 18;
/// The skin's thickness (mm): the body's outer surface less this is the subcutaneous fat's.
constexpr double KneeSkinMm = 2.0;
/// A structure's file-friendly name: "femur", "femur-marrow", "femoral-cartilage", "acl", "body"...
const char* KneeStructureName(KneeStructure structure);

struct KneeTissue {
  KneeLabel Label;
  std::string Name;   // e.g. "femur cortical"
  std::string Class;  // tissue class, a key of Resources/Materials/materials.json ("" for air)
  double CTHounsfield;   // mean CT value (HU)
  double MRIntensity;    // mean PD-MR value (arbitrary units, 0..1000)
  std::array<double, 3> Color;  // display colour (0..1)
};

/// All tissues, indexed by label value (entry 0 is background/air).
const std::vector<KneeTissue>& KneeTissues();

/// The four bones: segment ID and name used by the demo, surface, labels, and a display colour
/// per bone (so each bone can be told apart in pictures).
struct KneeBone {
  const char* ID;    // "femur"
  const char* Name;  // "Femur"
  KneeStructure Surface, Marrow;
  KneeLabel Cortical, Trabecular;
  std::array<double, 3> Color;
};
const std::array<KneeBone, 4>& KneeBones();

/// A voxel grid with arbitrary axes: RAS of voxel (i,j,k) = Origin + Σ Axes[c]·Spacing[c]·index[c].
struct KneeGrid {
  int Dims[3] = {0, 0, 0};
  double Spacing[3] = {1, 1, 1};
  double Axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // unit direction (RAS) of i, j, k
  double Origin[3] = {0, 0, 0};
  void VoxelCentre(int i, int j, int k, double ras[3]) const;
};
/// Voxels [Lo, Hi) of a grid, i fastest.
struct KneeGridBox {
  int Lo[3] = {0, 0, 0}, Hi[3] = {0, 0, 0};
  bool Empty() const { return Hi[0] <= Lo[0] || Hi[1] <= Lo[1] || Hi[2] <= Lo[2]; }
  size_t Size() const { return Empty() ? 0 : size_t(Hi[0] - Lo[0]) * (Hi[1] - Lo[1]) * (Hi[2] - Lo[2]); }
};

/// An anatomy: signed distances of its structures and the labelling rule.
class KneeModel {
 public:
  virtual ~KneeModel() = default;
  /// What the anatomy is, for reports.
  virtual std::string Description() const = 0;
  /// Signed distance (mm, < 0 inside).
  virtual double SignedDistance(KneeStructure structure, const double ras[3]) const = 0;
  bool Inside(KneeStructure structure, const double ras[3]) const { return this->SignedDistance(structure, ras) < 0.0; }
  /// A box (xmin, xmax, ymin, ymax, zmin, zmax) holding the structure's solid (its signed
  /// distance is positive outside the box). Infinite extents are allowed (the body).
  virtual void Bounds(KneeStructure structure, double bounds[6]) const = 0;
  /// Cortical shell thickness (mm) of a bone at a point near its surface.
  virtual double CorticalThickness(KneeStructure bone, const double ras[3]) const = 0;
  /// Tissue label at a point (the labelmap's rule, evaluated at any point).
  KneeLabel LabelAt(const double ras[3]) const;
  /// Points on a structure's surface, deterministic, roughly uniform; used to score meshes and
  /// registrations. Clipped to `boundsRAS` when given.
  virtual std::vector<std::array<double, 3>> SurfacePoints(KneeStructure structure, int count,
                                                           const double* boundsRAS = nullptr) const;
  /// The true surface as a closed mesh (RAS), when the anatomy has one (real surfaces; the
  /// analytic solids have none: nullptr).
  virtual vtkSmartPointer<vtkPolyData> Surface(KneeStructure structure) const;
  /// Signed distances at the voxel centres of `box` (into `out`, i fastest): exact where
  /// |d| <= `band`; farther away only the sign is guaranteed (|value| > band). The default
  /// evaluates SignedDistance at every voxel.
  virtual void SampleSignedDistance(KneeStructure structure, const KneeGrid& grid, const KneeGridBox& box,
                                    double band, float* out) const;
  /// The largest cortical thickness anywhere (bounds the band the renderer needs).
  virtual double MaxCorticalThickness() const = 0;
  /// Where the scanners centre their field of view (RAS): the leg's axis at the joint line.
  virtual void FieldOfViewCentre(double ras[3]) const { ras[0] = ras[1] = ras[2] = 0.0; }
  /// The knee's own lateral and anterior directions (RAS unit vectors, in the axial plane): a
  /// leg lies rotated in the scanner, and pictures look at the knee along its own axes.
  virtual void KneeAxes(double lateral[3], double anterior[3]) const {
    lateral[0] = 1, lateral[1] = 0, lateral[2] = 0;
    anterior[0] = 0, anterior[1] = 1, anterior[2] = 0;
  }
  /// Whether the tissues have the texture and density gradients of real bone (real anatomy) or
  /// are uniform (analytic solids: known means in every region).
  virtual bool RealisticTissue() const { return false; }
};

/// Analytic solids (the phantom before real anatomy): exact distances for capsules, spheres,
/// cylinders (shafts, ligaments), first-order (exact on the surface) for ellipsoids, smooth
/// unions and the tapered leg outline. Constant 2 mm cortex.
class KneeAnalyticModel : public KneeModel {
 public:
  std::string Description() const override { return "analytic knee (capsules, ellipsoids, smooth unions)"; }
  double SignedDistance(KneeStructure structure, const double ras[3]) const override;
  void Bounds(KneeStructure structure, double bounds[6]) const override;
  double CorticalThickness(KneeStructure, const double[3]) const override { return 2.0; }
  double MaxCorticalThickness() const override { return 2.0; }
};

enum class KneeAnatomy { Real, Analytic };
enum class KneePhantomSize { Small, Demo, Full };

struct KneePhantomOptions {
  KneeAnatomy Anatomy = KneeAnatomy::Real;
  /// Small (tests): CT 110x110x64 at 1.6x1.6x2.5 mm, MR 96x96x84 at 1.6x1.6x1.7 mm (sagittal).
  /// Demo: CT 220x220x128 at 0.8x0.8x1.25 mm, MR 192x192x84 at 0.8x0.8x1.7 mm.
  /// Full (benchmarks): CT 512x512x300 at 0.34x0.34x1.0 mm, MR 384x384x90 at 0.4x0.4x1.7 mm.
  /// The CT (176 mm across) is centred on the leg at the joint line; the MR on the knee where
  /// the MR sees it, a few millimetres off.
  KneePhantomSize Size = KneePhantomSize::Small;
  /// Explicit CT grid (used when all three are > 0): dimensions and spacing (mm).
  std::array<int, 3> CTDimensions = {0, 0, 0};
  std::array<double, 3> CTSpacing = {0, 0, 0};
  uint32_t Seed = 1;           // noise seed: same seed → identical volumes
  double CTNoiseHU = 15.0;     // Gaussian scanner noise (standard deviation, HU)
  double MRNoise = 12.0;       // Rician-like noise on the MR (standard deviation)
  bool GenerateCT = true;
  bool GenerateMR = true;
  bool GenerateLabels = true;  // labelmap on the CT grid
  /// True CT-to-MR rigid pose (RAS): rotation (degrees about x, y, z, applied in that order)
  /// then translation (mm). The MR sees the knee moved by this transform.
  std::array<double, 3> MRRotationDegrees = {6.0, -4.0, 10.0};
  std::array<double, 3> MRTranslation = {12.0, -8.0, 15.0};
};

struct KneePhantom {
  ImageVolume CT;      // short, HU; window/level set for bone
  ImageVolume MR;      // unsigned short, PD-like, 1.7 mm slices, MR pose
  ImageVolume Labels;  // unsigned char KneeLabel values on the CT grid
  /// Maps a point of the anatomy in CT RAS to the same anatomical point in MR RAS.
  vtkSmartPointer<vtkMatrix4x4> CTToMR = vtkSmartPointer<vtkMatrix4x4>::New();
  std::shared_ptr<const KneeModel> Model;
};

/// The real knee's anatomy (loaded once per process from Resources/Anatomy/KneeVHF, shared).
/// Null with `error` when the resources are missing or damaged.
std::shared_ptr<const KneeModel> LoadKneeSurfaceModel(std::string& error);

/// Generates the phantom (deterministic for given options). Returns false with `error` on
/// invalid options, missing anatomy or allocation failure; never throws. Uses up to 2 threads.
bool GenerateKneePhantom(const KneePhantomOptions& options, KneePhantom& phantom,
                         std::string& error, const ProgressCallback& progress = nullptr);

}  // namespace rp
