#include "rpRegisterCommand.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include <vtkPolyData.h>

#include "rpArgParser.h"
#include "rpModelIO.h"
#include "rpNodeStorage.h"
#include "rpTransformIO.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLandmarkRegistrationLogic.h"
#include "vtkRPLinearTransformNode.h"
#include "rpStrings.h"

namespace rp {

namespace {
// A figure to `digits` decimals, "n/a" when there is none (a degenerate fit's TRE).
std::string FixedOrNA(double value, int digits) { return std::isfinite(value) ? Fixed(value, digits) : "n/a"; }

const char* const Summary =
    "Paired-point registration of two fiducial lists (Slicer .mrk.json or .fcsv, paired by index; "
    "unselected points are left out): the rigid (or similarity) transform mapping the <from> points "
    "(e.g. landmarks digitized in Tracker coordinates) onto the <to> points (the same landmarks in the "
    "image, RAS), written as an ITK transform file Slicer opens unchanged (LPS, \"from parent\"; .tfm, "
    ".txt or .h5). FRE (seed eq. 8) only measures how well the fiducials fit each other; the accuracy "
    "to expect at a target is the predicted TRE (Fitzpatrick, West & Maurer 1998) from --fle.\n"
    "When the registration is rejected (FRE above --fre-threshold) or refused (fewer than 3 pairs, "
    "unequal counts, coincident or nearly collinear points) the command exits 1 with the reason and "
    "does NOT write --out: an existing file there is left as it was, so a stale-but-good transform is "
    "never silently replaced by a bad one. --json still prints the full result.\n"
    "Optional refinement: --icp-points (points digitized on the patient's surface, same space as <from>) "
    "and --icp-model (the surface, e.g. the bone model, in the <to> space) run a trimmed rigid ICP from "
    "the accepted landmark result; its residual is a surface distance, reported apart from FRE.";

nlohmann::json NumberOrNull(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

bool LoadFiducials(const std::string& path, vtkRPFiducialListNode* list, std::string& error) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage || storage->NodeClassForFiles() != "vtkRPFiducialListNode") {
    error = "'" + path + "' is not a fiducial file (use Slicer's .mrk.json or .fcsv)";
    return false;
  }
  return storage->Read(list, path, error);
}

// What the command was asked (parse options).
struct RegisterRequest {
  std::string From, To, Out, Mode, IcpPoints, IcpModel;
  double Threshold = 2.0, FLE = 0.25, Inliers = 0.9;
  std::vector<double> Target;
  bool ICP() const { return !this->IcpPoints.empty(); }
};

// What the logic made of it (run).
struct RegisterRun {
  vtkNew<vtkRPFiducialListNode> From, To, SurfacePoints;
  vtkNew<vtkRPLinearTransformNode> Output;
  vtkNew<vtkRPLandmarkRegistrationLogic> Logic;
  bool Accepted = false, IcpOk = true, Written = false;
  std::vector<std::string> Labels;  // of the pairs used (unselected pairs are skipped by the logic)
};

void DeclareOptions(ArgParser& parser) {
  const auto fiducialFiles = ExtensionsForNodeClass("vtkRPFiducialListNode");
  parser.Positional("from", "fiducials in the moving space (.mrk.json or .fcsv), e.g. digitized on the patient")
      .Input(FileKind::Points, fiducialFiles)
      .Positional("to", "the same landmarks, same order, in the fixed space (RAS), e.g. picked in the image")
      .Input(FileKind::Points, fiducialFiles)
      .Option("out", "transform", "transform file to write (.tfm, .txt or .h5); not written when rejected")
      .Output(FileKind::Transform, ExtensionsForNodeClass("vtkRPLinearTransformNode"))
      .Required()
      .Option("mode", "rigid|similarity", "rigid (rotation + translation) or similarity (+ isotropic scale)", "rigid")
      .OneOf()
      .Option("fre-threshold", "mm", "reject the registration when FRE exceeds this (0: no threshold)", "2")
      .Number()
      .AtLeast(0)
      .Option("fle", "mm",
              "prior RMS fiducial localization error for the predicted TRE: the tracker's specification "
              "(0.25 mm for a Polaris) plus the picking error in the image, added in quadrature",
              "0.25")
      .Number()
      .AtLeast(0)
      .Option("target", "r,a,s", "point (in the <to> space, RAS) where the TRE is predicted")
      .Point()
      .Option("icp-points", "fiducials", "surface points digitized in the <from> space (.mrk.json or .fcsv)")
      .Input(FileKind::Points, fiducialFiles)
      .Option("icp-model", "model", "surface model in the <to> space (" + ModelFileExtensionsText() + ")")
      .Input(FileKind::Model, ExtensionsForNodeClass("vtkRPModelNode"))
      .Option("icp-inliers", "fraction", "fraction of the surface points kept by the trimmed ICP", "0.9")
      .Number()
      .GreaterThan(0)
      .AtMost(1);
}

// Types, ranges, choices and --out were checked by the parser (declared above). False: bad arguments.
bool ParseRequest(const ArgParser& parser, RegisterRequest& request, std::ostream& err) {
  request.From = parser.Get("from");
  request.To = parser.Get("to");
  request.Out = parser.Get("out");
  request.Mode = parser.Get("mode");
  request.Threshold = parser.GetDouble("fre-threshold");
  request.FLE = parser.GetDouble("fle");
  request.Inliers = parser.GetDouble("icp-inliers");
  if (parser.Has("target")) request.Target = parser.GetDoubles("target", 3);
  if (parser.Has("icp-points") != parser.Has("icp-model")) {
    err << "roboplan register: --icp-points and --icp-model go together\n";
    return false;
  }
  if (parser.Has("icp-points")) {
    request.IcpPoints = parser.Get("icp-points");
    request.IcpModel = parser.Get("icp-model");
  }
  return true;
}

// Loads the fiducials and the surface, runs the module's logic (the panel's too), writes --out.
// False: an input could not be read (nothing run).
bool RunRegistration(const RegisterRequest& request, RegisterRun& run, std::ostream& err) {
  std::string error;
  vtkNew<vtkPolyData> surface;
  if (!LoadFiducials(request.From, run.From, error) || !LoadFiducials(request.To, run.To, error) ||
      (request.ICP() && (!LoadFiducials(request.IcpPoints, run.SurfacePoints, error) ||
                         !ReadModelFile(request.IcpModel, surface, error)))) {
    err << "roboplan register: " << error << "\n";
    return false;
  }
  vtkRPLandmarkRegistrationLogic* logic = run.Logic;
  logic->SetAutoUpdate(false);
  logic->SetFromFiducials(run.From);
  logic->SetToFiducials(run.To);
  logic->SetOutputTransform(run.Output);
  logic->SetMode(request.Mode == "similarity" ? RegistrationMode::Similarity : RegistrationMode::Rigid);
  logic->SetFREThreshold(request.Threshold);
  logic->SetFLE(request.FLE);
  if (!request.Target.empty()) logic->SetTarget(request.Target.data());
  run.Accepted = logic->Update();
  if (run.Accepted && request.ICP()) {
    SurfaceICPOptions icpOptions;
    icpOptions.InlierFraction = request.Inliers;
    run.IcpOk = logic->RefineWithSurfaceICP(run.SurfacePoints, surface, icpOptions);
    if (!run.IcpOk) err << "roboplan register: ICP refinement failed: " << logic->GetLastICPResult().Error << "\n";
  }
  if (run.Accepted && run.IcpOk) {
    run.Written = WriteTransformFile(request.Out, run.Output->GetMatrixTransformToParent(), error);
    if (!run.Written) err << "roboplan register: " << error << "\n";
  }
  if (run.From->GetNumberOfControlPoints() == run.To->GetNumberOfControlPoints()) {
    for (int i = 0; i < run.From->GetNumberOfControlPoints(); ++i) {
      if (run.From->GetNthControlPoint(i).Selected && run.To->GetNthControlPoint(i).Selected)
        run.Labels.push_back(run.To->GetNthControlPoint(i).Label);
    }
  }
  return true;
}

std::string PairLabel(const RegisterRun& run, size_t i) {
  return i < run.Labels.size() ? run.Labels[i] : std::to_string(i + 1);
}

// Report, --json.
nlohmann::json ResultJson(const RegisterRequest& request, const RegisterRun& run) {
  const RegistrationAssessment& a = run.Logic->GetLastAssessment();
  const SurfaceICPResult& icpResult = run.Logic->GetLastICPResult();
  nlohmann::json doc;
  doc["ok"] = run.Accepted && run.Written;
  doc["accepted"] = run.Accepted;
  doc["reason"] = a.Reason;
  doc["mode"] = request.Mode;
  doc["pairs"] = a.Solution.Residuals.size();
  doc["fre"] = NumberOrNull(a.Solution.FRE);
  doc["freThreshold"] = request.Threshold;
  doc["fle"] = request.FLE;
  doc["expectedFre"] = NumberOrNull(a.ExpectedFRE);
  doc["predictedTreAtCentroid"] = NumberOrNull(a.PredictedTREAtCentroid);
  doc["predictedTreMaxAtFiducials"] = NumberOrNull(a.MaxPredictedTREAtFiducials);
  if (!request.Target.empty())
    doc["target"] = {{"ras", request.Target}, {"predictedTre", NumberOrNull(a.PredictedTREAtTarget)}};
  nlohmann::json points = nlohmann::json::array();
  for (size_t i = 0; i < a.Solution.Residuals.size(); ++i) {
    nlohmann::json p = {{"label", PairLabel(run, i)},
                        {"residual", a.Solution.Residuals[i]},
                        {"leaveOneOut", i < a.LeaveOneOut.size() ? NumberOrNull(a.LeaveOneOut[i]) : nlohmann::json()}};
    points.push_back(p);
  }
  doc["fiducials"] = points;
  nlohmann::json suspects = nlohmann::json::array();
  for (const auto& s : a.Suspects)
    suspects.push_back({{"index", s.Index}, {"leaveOneOut", s.LeaveOneOut}, {"expected", s.Expected}, {"reason", s.Reason}});
  doc["suspects"] = suspects;
  doc["warnings"] = a.Warnings;
  if (request.ICP() && run.Accepted) {
    doc["icp"] = {{"ok", icpResult.Ok},           {"error", icpResult.Error},
                  {"inlierRmsMM", icpResult.InlierRMS}, {"allRmsMM", icpResult.AllRMS},
                  {"inliers", icpResult.Inliers},   {"points", run.SurfacePoints->GetNumberOfControlPoints()},
                  {"iterations", icpResult.Iterations}};
  }
  if (a.Solution.Ok) {
    const SimilarityTransform& chosen = request.ICP() && icpResult.Ok ? icpResult.Transform : a.Solution.Transform;
    const Eigen::Matrix4d m = chosen.Matrix();
    const Eigen::Matrix4d mt = m.transpose();
    doc["matrixToParentRAS"] = std::vector<double>(mt.data(), mt.data() + 16);  // row-major
    doc["scale"] = a.Solution.Transform.Scale;
  }
  doc["out"] = run.Written ? nlohmann::json(request.Out) : nlohmann::json();
  return doc;
}

// Report, text.
void WriteResultText(const RegisterRequest& request, const RegisterRun& run, std::ostream& out) {
  const RegistrationAssessment& a = run.Logic->GetLastAssessment();
  const SurfaceICPResult& icpResult = run.Logic->GetLastICPResult();
  out << "registration (" << request.Mode << ", " << a.Solution.Residuals.size() << " pairs): " << a.Reason << "\n";
  if (a.Solution.Ok) {
    out << "  FRE " << FixedOrNA(a.Solution.FRE, 3) << " mm (how well the fiducials fit; not the accuracy)";
    if (std::isfinite(a.ExpectedFRE))
      out << ", expected " << FixedOrNA(a.ExpectedFRE, 3) << " mm from FLE " << FixedOrNA(request.FLE, 3) << " mm";
    out << "\n";
    const std::vector<double>& target = request.Target;
    if (!target.empty())
      out << "  predicted TRE at the target (" << target[0] << ", " << target[1] << ", " << target[2]
          << "): " << FixedOrNA(a.PredictedTREAtTarget, 3) << " mm RMS\n";
    out << "  predicted TRE at the fiducials' centroid " << FixedOrNA(a.PredictedTREAtCentroid, 3)
        << " mm, at the worst fiducial " << FixedOrNA(a.MaxPredictedTREAtFiducials, 3) << " mm RMS\n";
    out << "  fiducial          residual  leave-one-out (mm)\n";
    for (size_t i = 0; i < a.Solution.Residuals.size(); ++i) {
      char line[160];
      std::snprintf(line, sizeof(line), "  %-16s %9s %14s\n", PairLabel(run, i).c_str(),
                    FixedOrNA(a.Solution.Residuals[i], 3).c_str(), FixedOrNA(a.LeaveOneOut[i], 3).c_str());
      out << line;
    }
  }
  for (const auto& w : a.Warnings) out << "  warning: " << w << "\n";
  if (request.ICP() && icpResult.Ok) {
    out << "  ICP refinement: " << icpResult.Iterations << " iterations, surface distance RMS "
        << FixedOrNA(icpResult.InlierRMS, 3) << " mm over the " << icpResult.Inliers << " kept of "
        << run.SurfacePoints->GetNumberOfControlPoints() << " points (" << FixedOrNA(icpResult.AllRMS, 3)
        << " mm over all; a surface fit, not FRE)\n";
  }
  if (run.Written) out << "wrote " << request.Out << "\n";
}

}  // namespace

int RunRegisterCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("register", Summary);
  DeclareOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  RegisterRequest request;
  if (!ParseRequest(parser, request, err)) return 2;
  RegisterRun run;
  if (!RunRegistration(request, run, err)) return 1;
  if (parser.Json()) {
    out << ResultJson(request, run).dump(2) << "\n";
  } else {
    WriteResultText(request, run, out);
  }
  if (!run.Accepted) {
    err << "roboplan register: " << run.Logic->GetLastAssessment().Reason << " (" << request.Out << " not written)\n";
    return 1;
  }
  return run.Written && run.IcpOk ? 0 : 1;
}

}  // namespace rp
