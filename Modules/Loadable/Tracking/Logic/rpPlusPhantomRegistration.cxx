#include "rpPlusPhantomRegistration.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <Eigen/LU>

#include "rpPivotCalibration.h"
#include "rpPlusConfiguration.h"
#include "rpPlusSequenceFile.h"
#include "rpRegistrationAccuracy.h"

namespace rp {

namespace {

/// The configuration as the shared PLUS parser reads it (one parser for every PLUS file).
plus::Configuration ReadConfiguration(const std::string& path) {
  plus::Configuration c;
  std::string error;
  if (!plus::ReadConfiguration(path, plus::ResolveOptions(), c, error)) throw std::runtime_error(error);
  return c;
}

/// PLUS's igsioMath::Round: halves away from zero.
double RoundHalfAway(double x) { return x < 0 ? std::ceil(x - 0.5) : std::floor(x + 0.5); }

void Take(const std::optional<double>& given, double& value) {
  if (given) value = *given;
}
void Take(const std::string& given, std::string& value) {
  if (!given.empty()) value = given;
}

/// Transform a→b of a frame of the recording: a direct transform, its inverse, or through Tracker.
bool FrameTransform(const PlusSequence& s, const PlusSequence::Frame& f, const std::string& a, const std::string& b,
                    Eigen::Matrix4d& out) {
  auto get = [&](const std::string& name, Eigen::Matrix4d& m) {
    const int i = s.TransformIndex(name);
    if (i < 0 || static_cast<size_t>(i) >= f.Transforms.size()) return false;
    const PlusSequence::Transform& t = f.Transforms[static_cast<size_t>(i)];
    if (!t.Present || t.State != ToolState::OK) return false;  // PLUS: the repository's status must be OK
    m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(t.Matrix);
    return true;
  };
  Eigen::Matrix4d m1, m2;
  if (get(a + "To" + b, out)) return true;
  if (get(b + "To" + a, m1)) {
    out = m1.inverse();
    return true;
  }
  if (get(a + "ToTracker", m1) && get(b + "ToTracker", m2)) {
    out = m2.inverse() * m1;  // as vtkIGSIOTransformRepository: (BToTracker)^-1 · AToTracker
    return true;
  }
  return false;
}

Eigen::Vector3d Translation(const Eigen::Matrix4d& m) { return m.block<3, 1>(0, 3); }

}  // namespace

/// A transform of CoordinateDefinitions, either way round (below).
bool FindCoordinateDefinition(const plus::Configuration& c, const std::string& from, const std::string& to,
                              Eigen::Matrix4d& matrix, double& error);

PlusPhantomConfiguration PlusPhantomConfiguration::Read(const std::string& path) {
  const plus::Configuration file = ReadConfiguration(path);
  const plus::PhantomRegistrationSettings& p = file.PhantomRegistration;
  PlusPhantomConfiguration c;
  Take(p.PhantomFrame, c.PhantomFrame);
  Take(p.ReferenceFrame, c.ReferenceFrame);
  Take(p.StylusTipFrame, c.StylusTipFrame);
  Take(p.StylusFrame, c.StylusFrame);
  Take(p.AcquisitionRate, c.AcquisitionRate);
  Take(p.FilterWindowTimeSec, c.FilterWindowTimeSec);
  Take(p.DetectionTimeSec, c.DetectionTimeSec);
  Take(p.StylusShaftMinimumDisplacementThresholdMm, c.StylusShaftMinimumDisplacementThresholdMm);
  Take(p.StylusTipMaximumDisplacementThresholdMm, c.StylusTipMaximumDisplacementThresholdMm);
  if (!(c.FilterWindowTimeSec > 0) || !(c.DetectionTimeSec > c.FilterWindowTimeSec))
    throw std::runtime_error(path + ": DetectionTimeSec must exceed FilterWindowTimeSec > 0");
  if (!p.HasLandmarks) throw std::runtime_error(path + ": no PhantomDefinition/Geometry/Landmarks (the phantom's landmark positions)");
  if (!p.LandmarkProblem.empty()) throw std::runtime_error(path + ": " + p.LandmarkProblem);
  for (const plus::PhantomLandmark& l : p.Landmarks) {
    c.LandmarkNames.push_back(l.Name);
    c.Landmarks.emplace_back(l.Position[0], l.Position[1], l.Position[2]);
  }
  if (c.Landmarks.size() < 3) throw std::runtime_error(path + ": " + std::to_string(c.Landmarks.size()) + " landmarks; at least 3 are needed");
  if (!FindCoordinateDefinition(file, c.StylusTipFrame, c.StylusFrame, c.StylusTipToStylus, c.StylusTipToStylusError))
    throw std::runtime_error(path + ": no CoordinateDefinitions transform " + c.StylusTipFrame + "To" + c.StylusFrame +
                             " (the stylus tip calibration; run pivot calibration first)");
  return c;
}

double PlusPhantomConfiguration::MinimumLandmarkDistance() const {
  double best = std::numeric_limits<double>::max();
  for (size_t i = 0; i < this->Landmarks.size(); ++i)
    for (size_t j = i + 1; j < this->Landmarks.size(); ++j) best = std::min(best, (this->Landmarks[i] - this->Landmarks[j]).norm());
  return best;
}

bool FindCoordinateDefinition(const plus::Configuration& c, const std::string& from, const std::string& to,
                              Eigen::Matrix4d& matrix, double& error) {
  for (const plus::FixedTransform& t : c.Transforms) {
    const bool direct = from == t.From && to == t.To, inverse = from == t.To && to == t.From;
    if (!direct && !inverse) continue;
    const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(t.Matrix);
    matrix = direct ? m : Eigen::Matrix4d(m.inverse());
    error = t.Error;
    return true;
  }
  const std::string name = from + "To" + to, inverse = to + "To" + from;
  for (const plus::Refusal& r : c.Refused)  // written, but unusable: say why
    if (r.What == "Transform " + name || r.What == "Transform " + inverse)
      throw std::runtime_error(c.Source + ": transform " + r.What.substr(10) + ": " + r.Why);
  return false;
}

bool ReadPlusCoordinateDefinition(const std::string& path, const std::string& from, const std::string& to,
                                  Eigen::Matrix4d& matrix, double& error) {
  return FindCoordinateDefinition(ReadConfiguration(path), from, to, matrix, error);
}

void PlusLandmarkDetector::Box::Add(const Eigen::Vector3d& p) {
  if (this->Empty) {
    this->Min = this->Max = p;
    this->Empty = false;
    return;
  }
  this->Min = this->Min.cwiseMin(p);
  this->Max = this->Max.cwiseMax(p);
}

PlusLandmarkDetector::PlusLandmarkDetector(const PlusPhantomConfiguration& config, double rate)
    : MinimumDistance(config.MinimumLandmarkDistance()),
      TipThreshold(config.StylusTipMaximumDisplacementThresholdMm),
      ShaftThreshold(config.StylusShaftMinimumDisplacementThresholdMm) {
  this->WindowSize = static_cast<unsigned>(std::max(1.0, RoundHalfAway(rate * config.FilterWindowTimeSec)));
  this->RequiredWindows = static_cast<unsigned>(config.DetectionTimeSec / config.FilterWindowTimeSec);
}

void PlusLandmarkDetector::Clear() {
  this->Poses.clear();
  this->Frames.clear();
  this->Tip = Box();
  this->Shaft = Box();
}

bool PlusLandmarkDetector::Insert(const Eigen::Matrix4d& tipToReference, double time, int frame) {
  this->Poses.push_back(tipToReference);
  this->Frames.push_back(frame);
  if (this->Poses.size() % this->WindowSize != 0) return false;
  // A window completed: its mean tip position, and a point 100 mm up the shaft (in StylusTip
  // coordinates, as PLUS puts it) now.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = this->Poses.size() - this->WindowSize; i < this->Poses.size(); ++i) mean += Translation(this->Poses[i]);
  this->Tip.Add(mean / this->WindowSize);
  this->Shaft.Add((tipToReference * Eigen::Vector4d(100, 0, 0, 1)).head<3>());
  if (this->Tip.Diagonal() > this->TipThreshold) {
    this->Clear();  // the tip moved: start over
    return false;
  }
  if (this->Poses.size() / this->WindowSize < this->RequiredWindows) return false;
  if (this->Shaft.Diagonal() < this->ShaftThreshold) return false;  // not pivoted enough yet
  const size_t before = this->Found.size();
  this->Estimate(time, frame);
  this->RestPoses = this->Poses;
  this->Clear();
  return this->Found.size() != before;
}

void PlusLandmarkDetector::Estimate(double time, int frame) {
  // PLUS (vtkPlusLandmarkDetectionAlgo::EstimateLandmarkPosition) assigns the number of windows to
  // skip (round(0.1 · windows) = 1 for 5 windows) to its window-size variable too, so it averages
  // the tip positions [skip·skip, windows·skip): with PLUS's defaults poses 1..4 of the rest.
  const unsigned skip = static_cast<unsigned>(RoundHalfAway(this->RequiredWindows * 0.1));
  const unsigned size = std::max(1u, skip);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  unsigned n = 0;
  for (size_t i = size * skip; i < this->Poses.size() && i < static_cast<size_t>(this->RequiredWindows) * size; ++i, ++n) {
    sum += Translation(this->Poses[i]);
  }
  if (n == 0) return;
  const Eigen::Vector3d mean = sum / n;
  // A rest within a third of the smallest landmark spacing of one found before is that landmark again.
  for (const DetectedLandmark& d : this->Found)
    if ((d.Position - mean).norm() < this->MinimumDistance / 3) return;
  DetectedLandmark d;
  d.Position = mean;
  d.Time = time;
  d.FirstFrame = this->Frames.front();
  d.LastFrame = frame;
  double spread = 0;
  for (const Eigen::Matrix4d& p : this->Poses) spread += (Translation(p) - mean).squaredNorm();
  d.SpreadMm = std::sqrt(spread / this->Poses.size());
  this->Found.push_back(d);
}

namespace {

/// The landmark of a rest as the pivot point of its poses (least squares, tip calibration free).
bool PivotLandmark(const std::vector<Eigen::Matrix4d>& poses, Eigen::Vector3d& point) {
  std::vector<ToolPose> tool;
  for (const Eigen::Matrix4d& m : poses) {
    const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> r = m;
    ToolPose p;
    p.FromMatrix(r.data());
    p.State = ToolState::OK;
    tool.push_back(p);
  }
  const PivotResult pivot = PivotCalibrate(tool, std::numeric_limits<double>::max(), 3.0);
  if (!pivot.Valid) return false;
  point = Eigen::Vector3d(pivot.PivotPoint[0], pivot.PivotPoint[1], pivot.PivotPoint[2]);
  return true;
}

}  // namespace

PhantomRegistrationResult RegisterPhantomFromRecording(const PlusSequence& recording, const PlusPhantomConfiguration& config,
                                                       LandmarkDetectionMethod method) {
  PhantomRegistrationResult r;
  r.Method = method;
  // PLUS's test reads the recording with REQUIRE_UNIQUE_TIMESTAMP: a frame whose time stamp repeats
  // the previous kept frame's is dropped before anything else (the rate below included).
  std::vector<size_t> kept;
  for (size_t f = 0; f < recording.Frames.size(); ++f)
    if (kept.empty() || recording.Frames[f].Timestamp != recording.Frames[kept.back()].Timestamp) kept.push_back(f);
  r.FramesSkipped = static_cast<int>(recording.Frames.size() - kept.size());
  if (kept.size() < 2) {
    r.Error = "the recording has " + std::to_string(kept.size()) + " frames with distinct time stamps";
    return r;
  }
  double rate = config.AcquisitionRate;
  if (!(rate > 0)) {  // PLUS's test: the rate of the first two (kept) frames, not the mean rate
    const double dt = recording.Frames[kept[1]].Timestamp - recording.Frames[kept[0]].Timestamp;
    if (!(dt > 0)) {
      r.Error = "the first two frames' time stamps do not increase: give AcquisitionRate in vtkPlusPhantomLandmarkRegistrationAlgo";
      return r;
    }
    rate = 1.0 / dt;
  }
  PlusLandmarkDetector detector(config, rate);
  const size_t wanted = config.Landmarks.size();
  for (size_t k = 0; k < kept.size() && r.Landmarks.size() < wanted; ++k) {
    const size_t f = kept[k];
    const PlusSequence::Frame& frame = recording.Frames[f];
    Eigen::Matrix4d stylusToReference;
    if (!FrameTransform(recording, frame, config.StylusFrame, config.ReferenceFrame, stylusToReference)) {
      ++r.FramesSkipped;  // PLUS skips a frame without a valid StylusToReference
      continue;
    }
    ++r.FramesUsed;
    if (!detector.Insert(stylusToReference * config.StylusTipToStylus, frame.Timestamp, static_cast<int>(f))) continue;
    DetectedLandmark landmark = detector.Landmarks().back();
    if (method == LandmarkDetectionMethod::Pivot && !PivotLandmark(detector.LastRest(), landmark.Position)) {
      r.Error = "the rest on landmark " + config.LandmarkNames[r.Landmarks.size()] + " has too little pivoting for a pivot point";
      return r;
    }
    r.Landmarks.push_back(landmark);
  }
  if (r.Landmarks.size() < wanted) {
    r.Error = "found " + std::to_string(r.Landmarks.size()) + " of the " + std::to_string(wanted) +
              " landmarks (the stylus must rest on each, in the configuration's order, and pivot there)";
    if (r.FramesUsed == 0)
      r.Error += "; no frame has a valid " + config.StylusFrame + "To" + config.ReferenceFrame + " (transforms in the recording: " +
                 [&] {
                   std::string names;
                   for (const auto& n : recording.TransformNames) names += (names.empty() ? "" : ", ") + n;
                   return names;
                 }() + ")";
    return r;
  }
  PointList detected;
  for (const DetectedLandmark& d : r.Landmarks) detected.push_back(d.Position);
  const PairedPointResult solution = RegisterPairedPoints(config.Landmarks, detected);
  if (!solution.Ok) {
    r.Error = solution.Error;
    return r;
  }
  r.PhantomToReference = solution.Transform.Matrix();
  r.FRE = solution.FRE;
  r.Residuals = solution.Residuals;
  for (double d : solution.Residuals) r.PlusErrorMm += d / solution.Residuals.size();
  const double n = static_cast<double>(detected.size());
  r.EstimatedFLE = n > 2 ? r.FRE / std::sqrt(1.0 - 2.0 / n) : 0;
  const TREPredictor tre(detected, r.EstimatedFLE);
  r.PredictedTREAtCentroid = tre.PredictRMS(tre.Centroid());
  for (const Eigen::Vector3d& p : detected) r.MaxPredictedTREAtLandmarks = std::max(r.MaxPredictedTREAtLandmarks, tre.PredictRMS(p));
  r.Ok = true;
  return r;
}

void PoseDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& mm, double& degrees) {
  mm = (Translation(a) - Translation(b)).norm();
  degrees = RotationDifferenceDegrees(a.block<3, 3>(0, 0), b.block<3, 3>(0, 0));
}

}  // namespace rp
