#pragma once
// Phantom registration from a PLUS recording and a PLUS device-set configuration, as fCal's
// "Phantom registration" with automatic landmark detection does (PLUS's
// vtkPlusLandmarkDetectionAlgo + vtkPlusPhantomLandmarkRegistrationAlgo): the stylus rests on each
// landmark of the phantom (PhantomDefinition/Geometry/Landmarks, in their order) and pivots there;
// the landmark is where the stylus tip (StylusTipToStylus from CoordinateDefinitions) stayed while
// the shaft moved; the rigid transform that maps the defined landmarks onto the detected ones is
// PhantomToReference.
//
// Two ways to find each landmark:
//  - Plus: PLUS's detector, step for step (windows of FilterWindowTimeSec; the tip's window means
//    within StylusTipMaximumDisplacementThresholdMm over DetectionTimeSec while a point 100 mm up
//    the shaft covered StylusShaftMinimumDisplacementThresholdMm; the landmark is the mean of the
//    few tip positions PLUS averages). On PLUS's recording it lands 0.086 mm / 0.128 deg from PLUS's
//    baseline PhantomToReference (PLUS's own test accepts 0.1 mm / 0.2 deg).
//  - Pivot: the same rests, but each landmark is the pivot point of every pose of its rest (least
//    squares, as pivot calibration), which does not depend on the tip calibration's error, but
//    needs more pivoting than PLUS asks for (on PLUS's recording it is 1.7 mm / 2.2 deg off).
// As PLUS's test reads the recording, a frame repeating the previous time stamp is dropped first,
// and the detector's rate is that of the first two frames kept. The registration itself is ours
// (rp::RegisterPairedPoints, Horn's quaternion: ITK's LandmarkBasedTransformInitializer with the
// VersorRigid3DTransform that PLUS calls gives the same transform to 1e-6 mm on PLUS's recording).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rpPairedPointRegistration.h"

namespace rp {

struct PlusSequence;

/// What the registration reads from a PLUS configuration (and PLUS's result files).
struct PlusPhantomConfiguration {
  std::vector<std::string> LandmarkNames;
  PointList Landmarks;  // Phantom coordinates, mm
  Eigen::Matrix4d StylusTipToStylus = Eigen::Matrix4d::Identity();
  double StylusTipToStylusError = -1;  // the configuration's Error attribute (-1: none)
  std::string PhantomFrame = "Phantom", ReferenceFrame = "Reference", StylusTipFrame = "StylusTip", StylusFrame = "Stylus";
  // vtkPlusPhantomLandmarkRegistrationAlgo's optional attributes (PLUS's defaults).
  double AcquisitionRate = 0;  // frames/s; 0: from the first two frames (as PLUS's test does)
  double FilterWindowTimeSec = 0.2, DetectionTimeSec = 1.0;
  double StylusShaftMinimumDisplacementThresholdMm = 30, StylusTipMaximumDisplacementThresholdMm = 1.5;

  /// Reads a PlusConfiguration file. Throws std::runtime_error naming the file and what is missing.
  static PlusPhantomConfiguration Read(const std::string& path);
  /// The smallest distance between two defined landmarks (PLUS's MinimunDistanceBetweenTwoLandmarksMm).
  double MinimumLandmarkDistance() const;
};

/// A CoordinateDefinitions transform From→To of a PLUS configuration or result file (the inverse
/// when only To→From is written). False when absent; `error` gets the Error attribute or -1.
bool ReadPlusCoordinateDefinition(const std::string& path, const std::string& from, const std::string& to,
                                  Eigen::Matrix4d& matrix, double& error);

enum class LandmarkDetectionMethod { Plus, Pivot };

struct DetectedLandmark {
  Eigen::Vector3d Position = Eigen::Vector3d::Zero();  // Reference coordinates
  double Time = 0;                                      // recording time when it was detected
  int FirstFrame = 0, LastFrame = 0;                    // the rest it was found in
  double SpreadMm = 0;                                  // RMS distance of the rest's tip positions from it
};

/// PLUS's landmark detector fed one StylusTipToReference pose at a time.
class PlusLandmarkDetector {
 public:
  PlusLandmarkDetector(const PlusPhantomConfiguration& config, double acquisitionRate);
  /// True when this pose completed a new landmark (then Landmarks().back() is it).
  bool Insert(const Eigen::Matrix4d& stylusTipToReference, double time, int frame);
  const std::vector<DetectedLandmark>& Landmarks() const { return this->Found; }
  /// The poses of the last rest (those the detector held when it fired), for the pivot method.
  const std::vector<Eigen::Matrix4d>& LastRest() const { return this->RestPoses; }

 private:
  struct Box {
    Eigen::Vector3d Min = Eigen::Vector3d::Zero(), Max = Eigen::Vector3d::Zero();
    bool Empty = true;
    void Add(const Eigen::Vector3d& p);
    double Diagonal() const { return this->Empty ? 0.0 : (this->Max - this->Min).norm(); }
  };
  void Clear();
  void Estimate(double time, int frame);
  unsigned WindowSize = 1, RequiredWindows = 1;
  double MinimumDistance, TipThreshold, ShaftThreshold;
  std::vector<Eigen::Matrix4d> Poses;
  std::vector<int> Frames;
  Box Tip, Shaft;
  std::vector<DetectedLandmark> Found;
  std::vector<Eigen::Matrix4d> RestPoses;
};

struct PhantomRegistrationResult {
  bool Ok = false;
  std::string Error;
  LandmarkDetectionMethod Method = LandmarkDetectionMethod::Plus;
  std::vector<DetectedLandmark> Landmarks;  // Reference coordinates, in the defined order
  Eigen::Matrix4d PhantomToReference = Eigen::Matrix4d::Identity();
  double PlusErrorMm = 0;   // PLUS's "registration error": the mean landmark distance
  double FRE = 0;           // RMS landmark distance (seed eq. 8)
  std::vector<double> Residuals;
  double EstimatedFLE = 0;  // from the FRE: FRE / sqrt(1 - 2/N)
  double PredictedTREAtCentroid = 0, MaxPredictedTREAtLandmarks = 0;  // with EstimatedFLE
  int FramesUsed = 0, FramesSkipped = 0;
};

/// Detects the landmarks in `recording` (transforms <Stylus>ToTracker and <Reference>ToTracker,
/// or <Stylus>To<Reference>) and registers. Never throws; Ok=false with Error.
PhantomRegistrationResult RegisterPhantomFromRecording(const PlusSequence& recording, const PlusPhantomConfiguration& config,
                                                       LandmarkDetectionMethod method = LandmarkDetectionMethod::Plus);

/// PLUS's comparison of two poses: the distance of the translations (mm) and the angle of
/// A·Bᵀ's rotation (degrees), as igsioMath::GetPositionDifference / GetOrientationDifference.
void PoseDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& mm, double& degrees);

}  // namespace rp
