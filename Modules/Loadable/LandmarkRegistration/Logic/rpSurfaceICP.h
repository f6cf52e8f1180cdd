#pragma once
// Refinement after the landmarks: trimmed rigid ICP of points digitized on the patient's
// surface (in the 'from' space, e.g. Tracker) to the model's surface (the 'to' space, RAS).
// Each iteration pairs every point with its closest point on the surface (vtkStaticCellLocator),
// keeps the closest fraction (trimming drops points digitized off the bone, in soft tissue or in
// the air) and solves for the rigid motion: point-to-plane (Chen & Medioni; converges in a few
// iterations on smooth surfaces, where point-to-point ICP slides for hundreds) or point-to-point
// (Besl & McKay, the paired-point solver). Its residual is a surface distance, not a
// fiducial error: it is reported separately from FRE.
#include <string>

#include "rpPairedPointRegistration.h"

class vtkPolyData;

namespace rp {

struct SurfaceICPOptions {
  int MaximumIterations = 100;
  double InlierFraction = 0.9;      // fraction of the points kept each iteration (trimmed ICP)
  double ToleranceMM = 1e-6;        // stop when no point moves more than this between iterations
  bool PointToPlane = true;
};

struct SurfaceICPResult {
  bool Ok = false;
  std::string Error;
  SimilarityTransform Transform;  // from → to, rigid
  int Iterations = 0;
  size_t Inliers = 0;
  double InlierRMS = 0;  // RMS distance of the kept points to the surface, mm
  double AllRMS = 0;     // RMS distance of all points to the surface, mm
};

SurfaceICPResult RefineWithSurfaceICP(const PointList& digitized, vtkPolyData* surface,
                                      const SimilarityTransform& initial, const SurfaceICPOptions& options = {});

}  // namespace rp
