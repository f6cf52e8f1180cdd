// Demo stages on the simulated NDI Polaris (a real serial protocol on a pseudo-terminal):
// pivot calibration of the stylus, patient-to-image registration with landmarks digitized by
// the tracked stylus (seed 2.3, 3.2.2, eq. 7-8), and navigation along a scripted tool path with
// the volume re-sliced at the tip (seed 3.3, 4).
//
// The "patient" stands in front of the camera at a known pose (TrackerToRAS truth), so the
// registration and the navigation can be scored even on a user's CT.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

#include <Eigen/Dense>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpBenchmarkChart.h"
#include "rpDemoStages.h"
#include "rpNdiTracker.h"
#include "rpPivotCalibration.h"
#include "rpPolarisSimulator.h"
#include "rpReport.h"
#include "rpResources.h"
#include "rpStageRunner.h"
#include "rpToolDefinition.h"
#include "rpTrackingRecording.h"
#include "rpTransformNames.h"
#include "rpVolumeReslice.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLandmarkRegistrationLogic.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// The true pose of the patient in the camera: RAS → tracker is a quarter turn about the
// vertical axis and the knee 1.45 m in front of the camera (inside the Polaris volume).
void TrueTrackerToRAS(vtkMatrix4x4* trackerToRAS) {
  vtkNew<vtkMatrix4x4> rasToTracker;
  const double c = std::cos(0.5), s = std::sin(0.5);
  const double m[16] = {c, 0, s, 15, 0, 1, 0, -25, -s, 0, c, -1450, 0, 0, 0, 1};
  rasToTracker->DeepCopy(m);
  vtkMatrix4x4::Invert(rasToTracker, trackerToRAS);
}

Eigen::Vector3d Apply(const vtkMatrix4x4* m, const Eigen::Vector3d& p) {
  const double in[4] = {p.x(), p.y(), p.z(), 1};
  double out[4];
  const_cast<vtkMatrix4x4*>(m)->MultiplyPoint(in, out);
  return {out[0], out[1], out[2]};
}

// Tracks one stylus trajectory on a fresh simulator + driver and returns every distinct frame:
// for `seconds`, and longer (up to 10 s more) until `minPoses` distinct frames
// are in: as a user holds the stylus on a landmark until the tracker has enough frames. On a
// loaded machine the 60 Hz frames arrive late; a fixed wall-clock window then saw too few.
std::vector<ToolPose> TrackStylus(const ToolDefinition& stylus, double seconds, size_t minPoses, uint32_t seed,
                                  std::string& stats) {
  PolarisSimulator::Options simOptions;
  simOptions.FrameRate = 60;
  simOptions.NoiseMm = 0.05;  // measurement jitter of a Polaris Spectra, per axis
  simOptions.NoiseDeg = 0.02;
  simOptions.Seed = seed;
  PolarisSimulator simulator(simOptions);
  simulator.AddTool(stylus);
  std::string error;
  if (!simulator.Start(error)) throw std::runtime_error("Polaris simulator: " + error);
  NdiTracker::Options options;
  options.Port = simulator.PortPath();
  options.Tools = {{stylus.Name, stylus.Rom}};
  options.RateCode = 2;  // 60 Hz
  NdiTracker tracker(options);
  tracker.Start();
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  while (tracker.GetState() != NdiTracker::State::Tracking && elapsed() < 15) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (tracker.GetState() != NdiTracker::State::Tracking) {
    const std::string why = tracker.LastError();
    tracker.Stop();
    simulator.Stop();
    throw std::runtime_error("the serial driver did not reach tracking on " + options.Port + ": " + why);
  }
  std::vector<ToolPose> poses;
  std::set<uint32_t> frames;
  const std::string slotName = ToolToTrackerName(stylus.Name);
  const int slot = tracker.Poses().Find(slotName.c_str(), slotName.size());
  const double trackingStart = elapsed();
  constexpr double maxExtraSeconds = 10;
  for (;;) {
    const double tracked = elapsed() - trackingStart;
    if (tracked >= seconds && (poses.size() >= minPoses || tracked >= seconds + maxExtraSeconds)) break;
    ToolPose pose;
    if (slot >= 0 && tracker.Poses().Read(slot, pose) && pose.State == ToolState::OK && frames.insert(pose.Frame).second) {
      poses.push_back(pose);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const auto s = tracker.GetStatistics();
  stats = std::to_string(s.Frames) + " frames, " + std::to_string(s.CrcErrors) + " CRC errors, " +
          std::to_string(s.FrameGaps) + " frame gaps, baud " + std::to_string(tracker.NegotiatedBaud());
  tracker.Stop();
  simulator.Stop();
  return poses;
}

// The activity log of a tracking session (seed 3.3: committed at the end): every pose as a
// recording that `roboplan pivot` and `roboplan track --replay` read back.
void WriteTrackingLog(DemoState& state, const std::string& file, const std::string& tool,
                      const std::vector<ToolPose>& poses) {
  RecordingWriter writer;
  std::string error;
  if (!writer.Open((fs::path(state.Output) / file).string(), error)) throw std::runtime_error(error);
  for (const ToolPose& pose : poses) writer.Add(tool.c_str(), pose.Timestamp, pose);
  writer.Close();
}

// Landmarks a surgeon would pick on bone: extreme points of the bone models (RAS).
std::vector<std::pair<std::string, Eigen::Vector3d>> PickBoneLandmarks(DemoState& state) {
  std::vector<Eigen::Vector3d> points;
  for (const auto& id : state.BoneModelIDs) {
    auto* model = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id));
    if (!model) continue;
    vtkPoints* p = model->GetPolyData()->GetPoints();
    for (vtkIdType i = 0; i < p->GetNumberOfPoints(); i += 7) {
      double x[3];
      p->GetPoint(i, x);
      points.emplace_back(x[0], x[1], x[2]);
    }
  }
  if (points.size() < 100) throw std::runtime_error("too few bone surface points to pick landmarks");
  double zmin = 1e300, zmax = -1e300;
  for (const auto& p : points) zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z());
  const double h = zmax - zmin;
  // The most extreme point in a direction within a height band (away from the cut ends).
  auto extreme = [&](const Eigen::Vector3d& direction, double zFrom, double zTo) {
    Eigen::Vector3d best = points.front();
    double score = -1e300;
    for (const auto& p : points) {
      if (p.z() < zmin + zFrom * h || p.z() > zmin + zTo * h) continue;
      if (p.dot(direction) > score) score = p.dot(direction), best = p;
    }
    return best;
  };
  return {{"lateral epicondyle", extreme({1, 0, 0}, 0.5, 0.7)},
          {"medial epicondyle", extreme({-1, 0, 0}, 0.5, 0.7)},
          {"patella", extreme({0, 1, 0}, 0.45, 0.75)},
          {"tibial tuberosity", extreme({0, 1, 0}, 0.2, 0.4)},
          {"anterior femur", extreme({0, 1, 0.3}, 0.75, 0.85)},
          {"posterior tibia", extreme({0, -1, 0}, 0.15, 0.35)}};
}

}  // namespace

void CalibrateStylus(DemoState& state) {
  const std::string stage = "Tracking";
  ToolDefinition stylus = ReadToolDefinition(ResourcePath("Tools/Stylus.json"));
  stylus.Motion.Type = ToolTrajectory::Pivot;
  stylus.Motion.Center[0] = 60;  // the divot, beside the patient
  stylus.Motion.Center[1] = 40;
  stylus.Motion.Center[2] = -1420;
  stylus.Motion.ConeAngleDeg = 25;
  stylus.Motion.PeriodSeconds = 2;
  std::string stats;
  state.Runner->Progress(0.1, "pivoting the stylus in the divot (simulated Polaris on a pty)");
  const auto poses = TrackStylus(stylus, 3.0, 90, 7, stats);
  WriteTrackingLog(state, "tracking-pivot.txt", stylus.Name, poses);
  // Scene: TrackerToRAS (set by the registration), StylusToTracker, and StylusTipToStylus under it
  // from the Tracking logic's calibration (as the panel calibrates).
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;
  trackerToRAS->SetName(TransformName(TrackerFrameName, "RAS"));
  state.Scene->AddNode(trackerToRAS);
  vtkNew<vtkRPTrackedToolNode> stylusNode;
  stylusNode->SetName(ToolToTrackerName(stylus.Name));
  state.Scene->AddNode(stylusNode);
  stylusNode->SetAndObserveTransformNodeID(trackerToRAS->GetID());
  vtkNew<vtkRPTrackingLogic> tracking;
  tracking->SetScene(state.Scene);
  vtkRPLinearTransformNode* tip = nullptr;
  const PivotResult pivot = tracking->CalibratePivot(poses, stylusNode->GetName(), 1.0, 10.0, &tip);
  if (!pivot.Valid || !pivot.Accepted) throw std::runtime_error("pivot calibration refused: " + pivot.Message);
  state.StylusTip = pivot.TipOffset;
  state.StylusTruth = stylus;
  const double tipError = std::sqrt(std::pow(pivot.TipOffset[0] - stylus.TipOffset[0], 2) +
                                    std::pow(pivot.TipOffset[1] - stylus.TipOffset[1], 2) +
                                    std::pow(pivot.TipOffset[2] - stylus.TipOffset[2], 2));
  state.Report->AddFigure(stage, "poses tracked for the pivot calibration", double(poses.size()), "", stats);
  state.Report->AddFigureBelow(stage, "pivot calibration RMSE", pivot.Rmse, "mm", 1.0, "rejection threshold 1 mm");
  state.Report->AddFigureBelow(stage, "tip offset error (vs the stylus definition)", tipError, "mm", 0.5);
  state.TrackerToRASID = trackerToRAS->GetID();
  state.StylusToTrackerID = stylusNode->GetID();
  state.StylusTipToStylusID = tip->GetID();
}

void RegisterPatient(DemoState& state) {
  const std::string stage = "Patient registration";
  vtkNew<vtkMatrix4x4> truthTrackerToRAS, truthRASToTracker;
  TrueTrackerToRAS(truthTrackerToRAS);
  vtkMatrix4x4::Invert(truthTrackerToRAS, truthRASToTracker);
  const auto landmarks = PickBoneLandmarks(state);
  vtkNew<vtkRPFiducialListNode> image, physical;
  image->SetName("ImageLandmarks");
  physical->SetName("PhysicalLandmarks");
  state.Scene->AddNode(image);
  state.Scene->AddNode(physical);
  // FLE: where the surgeon puts the stylus tip on a bony landmark is uncertain by ~0.5 mm RMS.
  const double fle = 0.5;
  std::mt19937 rng(2024);
  std::normal_distribution<double> jitter(0.0, fle / std::sqrt(3.0));
  int n = 0;
  for (const auto& [label, ras] : landmarks) {
    state.Runner->Progress(double(n++) / landmarks.size(), "digitizing " + label);
    image->AddControlPoint(ras.data(), label);
    // Where the tip really is (tracker frame): the landmark plus the localisation error.
    const Eigen::Vector3d touched = Apply(truthRASToTracker, ras) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    ToolDefinition stylus = state.StylusTruth;
    stylus.Motion.Type = ToolTrajectory::Static;
    for (int i = 0; i < 3; ++i) {
      stylus.Motion.Center[i] = touched[i] - stylus.TipOffset[static_cast<size_t>(i)];  // identity orientation
      stylus.Motion.Euler[i] = 0;
    }
    std::string stats;
    const auto poses = TrackStylus(stylus, 0.4, 12, 100 + n, stats);
    if (poses.size() < 5) throw std::runtime_error("landmark '" + label + "': the stylus was not seen (" + stats + ")");
    // The tip seen by the tracker with the calibrated offset, averaged over the held frames.
    Eigen::Vector3d tip = Eigen::Vector3d::Zero();
    for (const ToolPose& pose : poses) {
      double m[16];
      pose.ToMatrix(m);
      for (int r = 0; r < 3; ++r) {
        tip[r] += m[4 * r + 0] * state.StylusTip[0] + m[4 * r + 1] * state.StylusTip[1] + m[4 * r + 2] * state.StylusTip[2] +
                  m[4 * r + 3];
      }
    }
    tip /= double(poses.size());
    physical->AddControlPoint(tip.data(), label);
  }
  // The target: the middle of the knee joint (between the epicondyles), where a surgeon works.
  const Eigen::Vector3d target = 0.5 * (landmarks[0].second + landmarks[1].second);
  auto* trackerToRAS = vtkRPLinearTransformNode::SafeDownCast(state.Scene->GetNodeByID(state.TrackerToRASID));
  if (!trackerToRAS) throw std::runtime_error("no TrackerToRAS node (the tracking stage did not run)");
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  logic->SetFromFiducials(physical);
  logic->SetToFiducials(image);
  logic->SetOutputTransform(trackerToRAS);
  logic->SetFREThreshold(2.0);
  logic->SetFLE(fle);
  logic->SetTarget(target.data());
  const bool accepted = logic->Update();
  const auto& assessment = logic->GetLastAssessment();
  state.Report->AddFigure(stage, "landmark pairs", double(landmarks.size()), "", "the seed uses four; six here");
  state.Report->AddFigureBelow(stage, "FRE (eq. 8) — a consistency check, not accuracy", assessment.Solution.FRE, "mm", 2.0,
                               "user threshold 2 mm; expected from FLE: " + std::to_string(assessment.ExpectedFRE).substr(0, 5) + " mm");
  if (!accepted) throw std::runtime_error("registration rejected: " + assessment.Reason);
  // True TRE at the target: where the registration sends the target's physical position.
  const Eigen::Vector3d physicalTarget = Apply(truthRASToTracker, target);
  const double trueTRE = (Apply(trackerToRAS->GetMatrixTransformToParent(), physicalTarget) - target).norm();
  state.Report->AddFigure(stage, "predicted TRE at the knee centre (Fitzpatrick 1998)", assessment.PredictedTREAtTarget, "mm",
                          "FLE " + std::to_string(fle).substr(0, 4) + " mm");
  state.Report->AddFigureBelow(stage, "true TRE at the knee centre (vs the patient's true pose)", trueTRE, "mm",
                               std::max(2.0, 3 * assessment.PredictedTREAtTarget),
                               "one trial; the prediction is an RMS over trials, so about 3x it bounds one trial");
  // Registration log: the transform's Registration.* attributes (FRE, residuals, predicted TRE,
  // status and reason) with the true TRE of this simulated session.
  {
    std::ofstream log(fs::path(state.Output) / "registration-log.txt");
    log << "# patient-to-image registration (RoboPlan demo)\n";
    for (const auto& [key, value] : trackerToRAS->GetAttributes()) log << key << " = " << value << "\n";
    log << "TrueTRE.KneeCentre = " << trueTRE << "\n";
  }
  // The tracked stylus now moves in image space; the physical landmarks are shown there too.
  physical->SetAndObserveTransformNodeID(trackerToRAS->GetID());
  // A TRE map over the bones for the viewer (scalar array "PredictedTRE").
  for (const auto& id : state.BoneModelIDs) {
    if (auto* model = vtkRPModelNode::SafeDownCast(state.Scene->GetNodeByID(id))) logic->UpdatePredictedTREMap(model->GetPolyData());
  }
}

void Navigate(DemoState& state) {
  const std::string stage = "Navigation";
  auto* tip = vtkRPLinearTransformNode::SafeDownCast(state.Scene->GetNodeByID(state.StylusTipToStylusID));
  auto* stylusNode = vtkRPTrackedToolNode::SafeDownCast(state.Scene->GetNodeByID(state.StylusToTrackerID));
  auto* trackerToRAS = vtkRPLinearTransformNode::SafeDownCast(state.Scene->GetNodeByID(state.TrackerToRASID));
  if (!tip || !stylusNode || !trackerToRAS) throw std::runtime_error("no tracked stylus (earlier stages did not run)");
  vtkNew<vtkMatrix4x4> truthTrackerToRAS, truthRASToTracker;
  TrueTrackerToRAS(truthTrackerToRAS);
  vtkMatrix4x4::Invert(truthTrackerToRAS, truthRASToTracker);
  // The scripted path: the stylus tip circles the middle of the knee, passing close to the bones.
  double bounds[6];
  state.CT->GetRASBounds(bounds);
  const Eigen::Vector3d centreRAS(0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]));
  ToolDefinition stylus = state.StylusTruth;
  stylus.Motion.Type = ToolTrajectory::Circle;
  const Eigen::Vector3d centreTracker = Apply(truthRASToTracker, centreRAS);
  for (int i = 0; i < 3; ++i) stylus.Motion.Center[i] = centreTracker[i] - stylus.TipOffset[static_cast<size_t>(i)];
  stylus.Motion.Radius = 0.2 * std::min(bounds[1] - bounds[0], bounds[3] - bounds[2]);
  stylus.Motion.PeriodSeconds = 3;
  std::string stats;
  state.Runner->Progress(0.1, "tracking the stylus along its path");
  const auto poses = TrackStylus(stylus, 3.0, 90, 555, stats);
  if (poses.size() < 30) throw std::runtime_error("too few stylus poses along the path (" + stats + ")");

  WriteTrackingLog(state, "tracking-navigation.txt", stylus.Name, poses);
  vtkNew<vtkRPNavigationLogic> navigation;
  navigation->SetScene(state.Scene);
  navigation->SetToolNodeID(tip->GetID());
  navigation->SetTargetModelNodeIDs(state.BoneModelIDs);
  navigation->SetWarningDistance(5.0);
  double minDistance = 1e300, worstTipError = 0;
  Eigen::Vector3d closestTip = centreRAS;
  int warnings = 0, pictures = 0;
  const bool savePictures = state.Options.Screenshots;
  for (size_t i = 0; i < poses.size(); ++i) {
    double m[16];
    poses[i].ToMatrix(m);
    vtkNew<vtkMatrix4x4> stylusToTracker;
    stylusToTracker->DeepCopy(m);
    const int previous = stylusNode->StartModify();
    stylusNode->SetMatrixTransformToParent(stylusToTracker);
    stylusNode->SetStatus(vtkRPTrackedToolNode::StatusOK);
    stylusNode->SetTimestamp(poses[i].Timestamp);
    stylusNode->EndModify(previous);  // the navigation logic updates on TransformModifiedEvent
    const auto& result = navigation->GetLastResult();
    if (result.Valid) {
      if (result.DistanceMM < minDistance) closestTip = Eigen::Vector3d(result.TipRAS[0], result.TipRAS[1], result.TipRAS[2]);
      minDistance = std::min(minDistance, result.DistanceMM);
      warnings += result.Warning;
    }
    // Tip in image space vs. where the true tip is (measured stylus pose with the true tip
    // offset, mapped by the true patient pose): pivot calibration + registration errors.
    Eigen::Vector3d tipTracker;
    for (int r = 0; r < 3; ++r)
      tipTracker[r] = m[4 * r] * stylus.TipOffset[0] + m[4 * r + 1] * stylus.TipOffset[1] + m[4 * r + 2] * stylus.TipOffset[2] + m[4 * r + 3];
    const Eigen::Vector3d trueTipRAS = Apply(truthTrackerToRAS, tipTracker);
    const Eigen::Vector3d shownTip(result.TipRAS[0], result.TipRAS[1], result.TipRAS[2]);
    worstTipError = std::max(worstTipError, (shownTip - trueTipRAS).norm());
    // Re-slice at the tip: axial, sagittal, coronal and the tool's plane, every ~quarter turn.
    if (savePictures && pictures < 4 && i % std::max<size_t>(1, poses.size() / 4) == 0) {
      vtkNew<vtkMatrix4x4> tipToWorld, sliceToRAS;
      tip->GetMatrixTransformToWorld(tipToWorld);
      ResliceOptions options;
      options.FieldOfView[0] = options.FieldOfView[1] = 120;
      const char* names[] = {"axial", "sagittal", "coronal", "tool"};
      const char* orientations[] = {"Axial", "Sagittal", "Coronal"};  // the viewer's frames
      for (int o = 0; o < 4; ++o) {
        if (o < 3) {
          vtkRPSliceNode::ComputeSliceToRAS(orientations[o], result.TipRAS, sliceToRAS);
        } else {
          vtkRPSliceNode::ComputeSliceToRASForTool(tipToWorld, sliceToRAS);
        }
        auto slice = ResliceVolume(state.CT, sliceToRAS, options);
        const std::string file = "navigation-" + std::to_string(pictures) + "-" + names[o] + ".png";
        std::string why;
        const bool drawn = DemoSlicePicture(state, slice, state.CT->GetWindow(), state.CT->GetLevel(), file, why);
        if (pictures == 0) {
          state.Report->AddPictureIf(drawn, stage, file,
                                     std::string("CT re-sliced at the tracked tip: ") + names[o] +
                                         (o == 3 ? " (the plane of the stylus shaft)" : "") + ", 120 mm field of view.",
                                     why);
        }
      }
      ++pictures;
    }
  }
  // 4-up pictures with the slices following the tip: where the path came closest to bone.
  std::string error;
  state.Report->AddPictureIf(DemoScreenshot(state, closestTip.data(), "", "navigation-4up.png", error), stage,
                             "navigation-4up.png",
                             "4-up at the closest approach of the tracked tip to bone: axial, 3D (models, slices, "
                             "stylus), sagittal, coronal; MR (registered) over CT.",
                             error);
  state.Report->AddFigure(stage, "tracked poses along the path", double(poses.size()), "", stats);
  state.Report->AddFigureBelow(stage, "shown tip vs true tip in image space (worst along the path)", worstTipError, "mm", 2.0,
                               "pivot calibration + registration + tracking together");
  state.Report->AddFigure(stage, "closest approach of the tip to bone", minDistance, "mm",
                          std::to_string(warnings) + " poses under the 5 mm warning distance");
}

}  // namespace rp
