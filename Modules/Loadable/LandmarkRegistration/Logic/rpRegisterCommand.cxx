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

namespace rp {

namespace {

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

std::string Fixed(double value, int digits = 3) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

nlohmann::json NumberOrNull(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

bool LoadFiducials(const std::string& path, vtkRPFiducialListNode* list, std::string& error) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage || storage->NodeClassForFiles() != "vtkRPFiducialListNode") {
    error = "'" + path + "' is not a fiducial file (use Slicer's .mrk.json or .fcsv)";
    return false;
  }
  return storage->Read(list, path, error);
}

}  // namespace

int RunRegisterCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("register", Summary);
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
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  // Types, ranges, choices and --out were checked by the parser (declared above).
  const std::string outPath = parser.Get("out");
  const std::string mode = parser.Get("mode");
  const double threshold = parser.GetDouble("fre-threshold"), fle = parser.GetDouble("fle");
  const double inliers = parser.GetDouble("icp-inliers");
  std::vector<double> target;
  if (parser.Has("target")) target = parser.GetDoubles("target", 3);
  if (parser.Has("icp-points") != parser.Has("icp-model")) {
    err << "roboplan register: --icp-points and --icp-model go together\n";
    return 2;
  }

  vtkNew<vtkRPFiducialListNode> from, to;
  std::string error;
  for (auto [path, list] : {std::pair{parser.Get("from"), from.GetPointer()}, std::pair{parser.Get("to"), to.GetPointer()}}) {
    if (!LoadFiducials(path, list, error)) {
      err << "roboplan register: " << error << "\n";
      return 1;
    }
  }
  vtkNew<vtkRPFiducialListNode> surfacePoints;
  vtkNew<vtkPolyData> surface;
  const bool icp = parser.Has("icp-points");
  if (icp) {
    if (!LoadFiducials(parser.Get("icp-points"), surfacePoints, error) ||
        !ReadModelFile(parser.Get("icp-model"), surface, error)) {
      err << "roboplan register: " << error << "\n";
      return 1;
    }
  }
  vtkNew<vtkRPLinearTransformNode> output;
  vtkNew<vtkRPLandmarkRegistrationLogic> logic;
  logic->SetAutoUpdate(false);
  logic->SetFromFiducials(from);
  logic->SetToFiducials(to);
  logic->SetOutputTransform(output);
  logic->SetMode(mode == "similarity" ? RegistrationMode::Similarity : RegistrationMode::Rigid);
  logic->SetFREThreshold(threshold);
  logic->SetFLE(fle);
  if (!target.empty()) logic->SetTarget(target.data());
  const bool accepted = logic->Update();
  const RegistrationAssessment& a = logic->GetLastAssessment();
  bool icpOk = true;
  if (accepted && icp) {
    SurfaceICPOptions icpOptions;
    icpOptions.InlierFraction = inliers;
    icpOk = logic->RefineWithSurfaceICP(surfacePoints, surface, icpOptions);
    if (!icpOk) err << "roboplan register: ICP refinement failed: " << logic->GetLastICPResult().Error << "\n";
  }
  const SurfaceICPResult& icpResult = logic->GetLastICPResult();

  bool written = false;
  if (accepted && icpOk) {
    written = WriteTransformFile(outPath, output->GetMatrixTransformToParent(), error);
    if (!written) {
      err << "roboplan register: " << error << "\n";
    }
  }

  // Labels of the pairs used (unselected pairs are skipped by the logic).
  std::vector<std::string> labels;
  if (from->GetNumberOfControlPoints() == to->GetNumberOfControlPoints()) {
    for (int i = 0; i < from->GetNumberOfControlPoints(); ++i) {
      if (from->GetNthControlPoint(i).Selected && to->GetNthControlPoint(i).Selected)
        labels.push_back(to->GetNthControlPoint(i).Label);
    }
  }

  if (parser.Json()) {
    nlohmann::json doc;
    doc["ok"] = accepted && written;
    doc["accepted"] = accepted;
    doc["reason"] = a.Reason;
    doc["mode"] = mode;
    doc["pairs"] = a.Solution.Residuals.size();
    doc["fre"] = NumberOrNull(a.Solution.FRE);
    doc["freThreshold"] = threshold;
    doc["fle"] = fle;
    doc["expectedFre"] = NumberOrNull(a.ExpectedFRE);
    doc["predictedTreAtCentroid"] = NumberOrNull(a.PredictedTREAtCentroid);
    doc["predictedTreMaxAtFiducials"] = NumberOrNull(a.MaxPredictedTREAtFiducials);
    if (!target.empty()) doc["target"] = {{"ras", target}, {"predictedTre", NumberOrNull(a.PredictedTREAtTarget)}};
    nlohmann::json points = nlohmann::json::array();
    for (size_t i = 0; i < a.Solution.Residuals.size(); ++i) {
      nlohmann::json p = {{"label", i < labels.size() ? labels[i] : std::to_string(i + 1)},
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
    if (icp && accepted) {
      doc["icp"] = {{"ok", icpResult.Ok},           {"error", icpResult.Error},
                    {"inlierRmsMM", icpResult.InlierRMS}, {"allRmsMM", icpResult.AllRMS},
                    {"inliers", icpResult.Inliers},   {"points", surfacePoints->GetNumberOfControlPoints()},
                    {"iterations", icpResult.Iterations}};
    }
    if (a.Solution.Ok) {
      const SimilarityTransform& chosen = icp && icpResult.Ok ? icpResult.Transform : a.Solution.Transform;
      const Eigen::Matrix4d m = chosen.Matrix();
      const Eigen::Matrix4d mt = m.transpose();
      doc["matrixToParentRAS"] = std::vector<double>(mt.data(), mt.data() + 16);  // row-major
      doc["scale"] = a.Solution.Transform.Scale;
    }
    doc["out"] = written ? nlohmann::json(outPath) : nlohmann::json();
    out << doc.dump(2) << "\n";
  } else {
    out << "registration (" << mode << ", " << a.Solution.Residuals.size() << " pairs): " << a.Reason << "\n";
    if (a.Solution.Ok) {
      out << "  FRE " << Fixed(a.Solution.FRE) << " mm (how well the fiducials fit; not the accuracy)";
      if (std::isfinite(a.ExpectedFRE)) out << ", expected " << Fixed(a.ExpectedFRE) << " mm from FLE " << Fixed(fle) << " mm";
      out << "\n";
      if (!target.empty())
        out << "  predicted TRE at the target (" << target[0] << ", " << target[1] << ", " << target[2]
            << "): " << Fixed(a.PredictedTREAtTarget) << " mm RMS\n";
      out << "  predicted TRE at the fiducials' centroid " << Fixed(a.PredictedTREAtCentroid)
          << " mm, at the worst fiducial " << Fixed(a.MaxPredictedTREAtFiducials) << " mm RMS\n";
      out << "  fiducial          residual  leave-one-out (mm)\n";
      for (size_t i = 0; i < a.Solution.Residuals.size(); ++i) {
        char line[160];
        std::snprintf(line, sizeof(line), "  %-16s %9s %14s\n",
                      (i < labels.size() ? labels[i] : std::to_string(i + 1)).c_str(),
                      Fixed(a.Solution.Residuals[i]).c_str(), Fixed(a.LeaveOneOut[i]).c_str());
        out << line;
      }
    }
    for (const auto& w : a.Warnings) out << "  warning: " << w << "\n";
    if (icp && icpResult.Ok) {
      out << "  ICP refinement: " << icpResult.Iterations << " iterations, surface distance RMS "
          << Fixed(icpResult.InlierRMS) << " mm over the " << icpResult.Inliers << " kept of "
          << surfacePoints->GetNumberOfControlPoints() << " points (" << Fixed(icpResult.AllRMS)
          << " mm over all; a surface fit, not FRE)\n";
    }
    if (written) out << "wrote " << outPath << "\n";
  }
  if (!accepted) {
    err << "roboplan register: " << a.Reason << " (" << outPath << " not written)\n";
    return 1;
  }
  return written && icpOk ? 0 : 1;
}

}  // namespace rp
