#pragma once
// The built-in knee phantom: a deterministic, analytic right knee (RAS, millimetres) rendered
// as a CT, a proton-density-like MR in a different pose, and the ground-truth labelmap.
//
// Anatomy frame (= CT RAS): the joint line is at z = 0, femur above (+S), tibia/fibula below,
// +x lateral (a right knee: patient's right), +y anterior (patella side).
// Every structure is an analytic solid with a signed distance (negative inside, in mm) so
// segmentation, meshing and registration can be scored against the truth.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rpImageVolume.h"
#include "rpProgress.h"

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

/// Structures with an analytic surface (a bone = cortical + trabecular together).
enum class KneeStructure {
  Femur, Tibia, Fibula, Patella,            // outer (periosteal) bone surfaces
  FemurMarrow, TibiaMarrow, FibulaMarrow, PatellaMarrow,  // trabecular cores
  FemoralCartilage, TibialCartilage, PatellarCartilage,
  ACL, PCL, MCL, LCL,
  Body  // skin outer surface
};

struct KneeTissue {
  KneeLabel Label;
  std::string Name;   // e.g. "femur cortical"
  std::string Class;  // tissue class for materials: "bone", "cartilage", "ligament", "muscle", "fat", "skin"
  double CTHounsfield;   // mean CT value (HU)
  double MRIntensity;    // mean PD-MR value (arbitrary units, 0..1000)
  std::array<double, 3> Color;  // display colour (0..1)
};

/// All tissues, indexed by label value (entry 0 is background/air).
const std::vector<KneeTissue>& KneeTissues();

/// The analytic model: inside tests and signed distances in anatomy (= CT RAS) coordinates.
class KneeModel {
 public:
  KneeModel();
  /// Signed distance (mm, < 0 inside). Exact for capsules/spheres/cylinders (shafts, ligaments);
  /// first-order (exact on the surface, accurate near it) for the ellipsoids (patella), the
  /// smooth unions (condyles, plateau) and the tapered elliptical leg outline (Body).
  double SignedDistance(KneeStructure structure, const double ras[3]) const;
  bool Inside(KneeStructure structure, const double ras[3]) const {
    return this->SignedDistance(structure, ras) < 0.0;
  }
  /// Tissue label at a point (the labelmap's rule, evaluated at any point).
  KneeLabel LabelAt(const double ras[3]) const;
  /// Points on a structure's surface (|signed distance| < 0.01 mm), deterministic, roughly
  /// uniform; used to score meshes and registrations. Clipped to `boundsRAS` when given.
  std::vector<std::array<double, 3>> SurfacePoints(KneeStructure structure, int count,
                                                   const double* boundsRAS = nullptr) const;
  /// Cortical shell thickness (mm) used by the labelmap rule.
  double CorticalThickness() const { return 2.0; }
};

enum class KneePhantomSize { Small, Full };

struct KneePhantomOptions {
  /// Small: CT 96x96x64 at 1.6x1.6x2.5 mm (~0.6 M voxels, ~0.3 s CPU), MR 96x96x84 at
  /// 1.6x1.6x1.7 mm (sagittal). Full: CT 512x512x300 at 0.3x0.3x1.0 mm, MR 384x384x90 at
  /// 0.4x0.4x1.7 mm (benchmarks). Both grids are centred near the knee; the MR's is not the CT's.
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

/// Generates the phantom (deterministic for given options). Returns false with `error` on
/// invalid options or allocation failure; never throws. Uses up to 2 threads.
bool GenerateKneePhantom(const KneePhantomOptions& options, KneePhantom& phantom,
                         std::string& error, const ProgressCallback& progress = nullptr);

}  // namespace rp
