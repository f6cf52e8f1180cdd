#pragma once
// Rigid multi-modality (CT <-> MR) registration by voxel similarity: ITK v4 registration
// (ImageRegistrationMethodv4), Mattes mutual information, versor rigid transform, regular
// step gradient descent, multi-resolution (shrink + smoothing), with progress and cancel.
//
// Conventions: volumes are RAS (IJK-to-RAS); ITK works in LPS inside. The result is given
// both ways: FixedToMoving maps a point of the fixed volume's RAS to the same anatomy in the
// moving volume's RAS (ITK's "from parent" resampling transform, what a .tfm file holds, in
// RAS), MovingToFixed is its inverse = the "to parent" matrix of a transform node that puts
// the moving volume onto the fixed one (e.g. "MRToCT").
//
// Declared here, in RoboPlanImaging; the ITK work is libRoboPlanVolumeRegistration.so beside it,
// loaded on the first registration (rpVolumeRegistrationEntry.h): a caller links RoboPlanImaging only.
#include <array>
#include <atomic>
#include <string>
#include <vector>

#include <vtkMatrix4x4.h>
#include <vtkSmartPointer.h>

#include "rpImageVolume.h"
#include "rpProgress.h"

namespace rp {

struct RigidRegistrationOptions {
  /// Start: fixed RAS → moving RAS (identity = the scanners' coordinates are trusted).
  vtkSmartPointer<vtkMatrix4x4> InitialFixedToMoving;
  /// Instead of the start above, align the volumes' geometric centres first.
  bool InitializeByGeometryCentres = false;
  /// Four levels: the 8x level gives the capture range (20-30 degrees, 30-40 mm on the
  /// phantom), the full-resolution level the accuracy.
  std::vector<unsigned> ShrinkFactors = {8, 4, 2, 1};
  std::vector<double> SmoothingSigmasMM = {6.0, 3.0, 1.5, 0.0};  // physical units
  unsigned MaxIterationsPerLevel = 200;
  unsigned HistogramBins = 32;
  double SamplingFraction = 0.1;   // random sampling of the fixed image per level
  double InitialStepMM = 4.0;      // first step of each level (physical shift, mm)
  double MinimumStepMM = 0.02;     // convergence at the last level (earlier ones: x shrink^2)
  double RelaxationFactor = 0.7;   // step shrink when the gradient turns back
  unsigned RandomSeed = 121212;    // sampling seed (deterministic results)
};

struct RigidRegistrationResult {
  vtkSmartPointer<vtkMatrix4x4> FixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();
  vtkSmartPointer<vtkMatrix4x4> MovingToFixed = vtkSmartPointer<vtkMatrix4x4>::New();
  bool Converged = false;
  std::string StopReason;        // the optimizer's stop condition at the last level
  double FinalMetric = 0.0;      // Mattes MI (negative: lower is better)
  unsigned Iterations = 0;       // total over all levels
  double Seconds = 0.0;
};

/// Registers `moving` to `fixed`. Returns false with `error` on bad input, cancel or an ITK
/// exception, or when the registration library cannot be loaded (`error` names the file and why);
/// returns true with `Converged == false` (and the reason) when the optimizer ran out of
/// iterations at the finest level: callers must not silently accept that result.
bool RegisterVolumesRigid(const ImageVolume& fixed, const ImageVolume& moving, const RigidRegistrationOptions& options,
                          RigidRegistrationResult& result, std::string& error,
                          const ProgressCallback& progress = nullptr, const std::atomic<bool>* cancel = nullptr);

/// RMS distance (mm) between where two fixed→moving transforms send the given points.
double TransformRMSDifference(const vtkMatrix4x4* a, const vtkMatrix4x4* b,
                              const std::vector<std::array<double, 3>>& points);

}  // namespace rp
