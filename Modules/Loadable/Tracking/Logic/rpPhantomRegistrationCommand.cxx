#include "rpPhantomRegistrationCommand.h"

#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUtilities.h>

#include "rpArgParser.h"
#include "rpPlusPhantomRegistration.h"
#include "rpXmlDocument.h"
#include "vtkRPTrackingLogic.h"

namespace rp {

namespace {

const char* const Summary =
    "Phantom registration from a PLUS recording, as fCal's automatic landmark detection: the stylus "
    "rests and pivots on each landmark of the configuration's PhantomDefinition, in its order; the tip "
    "(StylusTipToStylus from CoordinateDefinitions) gives each landmark in Reference coordinates; the "
    "rigid fit of the defined landmarks onto them is PhantomToReference. --method plus finds the "
    "landmarks exactly as PLUS does (reproduces PLUS's result); --method pivot takes each as the pivot "
    "point of its rest (independent of the tip calibration). FRE is the RMS landmark distance, PLUS's "
    "error figure the mean one; the predicted TRE uses the FLE the FRE implies.";

std::string MatrixText(const Eigen::Matrix4d& m) {
  std::ostringstream s;
  s.precision(9);
  for (int r = 0; r < 4; ++r) {
    s << "\n        ";
    for (int c = 0; c < 4; ++c) s << m(r, c) << (c < 3 ? "\t" : "");
  }
  return s.str();
}

/// The configuration with From→To (re)placed in CoordinateDefinitions, written atomically by VTK.
bool WriteConfigurationWith(const std::string& configPath, const std::string& outPath, const std::string& from,
                            const std::string& to, const Eigen::Matrix4d& m, double errorMm, std::string& error) {
  vtkSmartPointer<vtkXMLDataElement> root = ReadXmlFile(configPath, error);
  if (!root) return false;
  vtkXMLDataElement* defs = root->FindNestedElementWithName("CoordinateDefinitions");
  if (!defs) {
    vtkNew<vtkXMLDataElement> created;
    created->SetName("CoordinateDefinitions");
    root->AddNestedElement(created);
    defs = created;
  }
  for (int i = defs->GetNumberOfNestedElements() - 1; i >= 0; --i) {
    vtkXMLDataElement* t = defs->GetNestedElement(i);
    const char* f = t->GetAttribute("From");
    const char* o = t->GetAttribute("To");
    if (f && o && ((from == f && to == o) || (from == o && to == f))) defs->RemoveNestedElement(t);
  }
  vtkNew<vtkXMLDataElement> t;
  t->SetName("Transform");
  t->SetAttribute("From", from.c_str());
  t->SetAttribute("To", to.c_str());
  t->SetAttribute("Matrix", MatrixText(m).c_str());
  t->SetDoubleAttribute("Error", errorMm);
  defs->AddNestedElement(t);
  if (!vtkXMLUtilities::WriteElementToFile(root, outPath.c_str())) {
    error = "cannot write " + outPath;
    return false;
  }
  return true;
}

nlohmann::json ToJson(const PhantomRegistrationResult& r, const PlusPhantomConfiguration& c) {
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> m = r.PhantomToReference;
  nlohmann::json landmarks = nlohmann::json::array();
  for (size_t i = 0; i < r.Landmarks.size(); ++i) {
    const DetectedLandmark& d = r.Landmarks[i];
    landmarks.push_back({{"name", c.LandmarkNames[i]},
                         {"reference", {d.Position.x(), d.Position.y(), d.Position.z()}},
                         {"time", d.Time},
                         {"frames", {d.FirstFrame, d.LastFrame}},
                         {"residualMm", i < r.Residuals.size() ? r.Residuals[i] : 0.0}});
  }
  return {{"method", r.Method == LandmarkDetectionMethod::Plus ? "plus" : "pivot"},
          {"phantomToReference", std::vector<double>(m.data(), m.data() + 16)},
          {"landmarks", landmarks},
          {"freMm", r.FRE},
          {"plusErrorMm", r.PlusErrorMm},
          {"estimatedFleMm", r.EstimatedFLE},
          {"predictedTreAtCentroidMm", r.PredictedTREAtCentroid},
          {"maxPredictedTreAtLandmarksMm", r.MaxPredictedTREAtLandmarks},
          {"framesUsed", r.FramesUsed},
          {"framesSkipped", r.FramesSkipped}};
}

void PrintText(const PhantomRegistrationResult& r, const PlusPhantomConfiguration& c, std::ostream& out) {
  out << c.PhantomFrame << "To" << c.ReferenceFrame << " (" << (r.Method == LandmarkDetectionMethod::Plus ? "PLUS" : "pivot")
      << " landmark detection):" << MatrixText(r.PhantomToReference) << "\n";
  char line[200];
  for (size_t i = 0; i < r.Landmarks.size(); ++i) {
    const DetectedLandmark& d = r.Landmarks[i];
    std::snprintf(line, sizeof line, "  landmark %-4s at t=%8.3f s (frames %d-%d): %9.3f %9.3f %9.3f  residual %.3f mm\n",
                  c.LandmarkNames[i].c_str(), d.Time, d.FirstFrame, d.LastFrame, d.Position.x(), d.Position.y(),
                  d.Position.z(), r.Residuals[i]);
    out << line;
  }
  std::snprintf(line, sizeof line,
                "FRE %.3f mm RMS (PLUS's error figure, the mean landmark distance: %.3f mm); predicted TRE %.3f mm RMS at "
                "the landmarks' centroid, %.3f mm at the worst landmark (FLE %.3f mm implied by the FRE)\n",
                r.FRE, r.PlusErrorMm, r.PredictedTREAtCentroid, r.MaxPredictedTREAtLandmarks, r.EstimatedFLE);
  out << line;
}

}  // namespace

int RunPhantomRegistrationCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("phantom-registration", Summary);
  parser.Positional("recording", "PLUS tracked-frame sequence (.igs.mha, .igs.nrrd) of the stylus on the landmarks")
      .Input(FileKind::Any, {".mha", ".nrrd", ".mhd"})
      .Option("plus-config", "xml", "PLUS device-set configuration (PhantomDefinition, StylusTipToStylus)")
      .Input(FileKind::Any, {".xml"})
      .Required()
      .Option("method", "plus|pivot", "how each landmark is found: plus (as PLUS) or pivot (pivot point of its rest)", "plus")
      .OneOf()
      .Option("compare", "xml", "a PLUS result (CoordinateDefinitions with PhantomToReference) to compare with")
      .Input(FileKind::Any, {".xml"})
      .Option("tolerance-mm", "mm", "with --compare: exit 1 when the translations differ more (PLUS's own test: 0.1)", "0.1")
      .Number()
      .AtLeast(0)
      .Option("tolerance-deg", "deg", "with --compare: exit 1 when the rotations differ more (PLUS's own test: 0.2)", "0.2")
      .Number()
      .AtLeast(0)
      .Option("out", "xml", "write the configuration with PhantomToReference added, as fCal saves it")
      .Output(FileKind::Any, {".xml"});
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  const LandmarkDetectionMethod method = parser.Get("method") == "pivot" ? LandmarkDetectionMethod::Pivot : LandmarkDetectionMethod::Plus;
  PlusPhantomConfiguration config;
  vtkNew<vtkRPTrackingLogic> logic;  // no scene: the command reports the registration, applies none
  const PhantomRegistrationResult r = logic->RegisterPhantom(parser.Get("recording"), parser.Get("plus-config"), method, config);
  if (!r.Ok) {
    err << "roboplan phantom-registration: " << r.Error << "\n";
    return 1;
  }
  nlohmann::json doc = ToJson(r, config);
  if (!parser.Json()) PrintText(r, config, out);
  int code = 0;
  if (parser.Has("compare")) {
    Eigen::Matrix4d plus;
    double plusError = -1, mm = 0, deg = 0;
    try {
      if (!ReadPlusCoordinateDefinition(parser.Get("compare"), config.PhantomFrame, config.ReferenceFrame, plus, plusError))
        throw std::runtime_error(parser.Get("compare") + " has no " + config.PhantomFrame + "To" + config.ReferenceFrame);
    } catch (const std::exception& e) {
      err << "roboplan phantom-registration: " << e.what() << "\n";
      return 1;
    }
    PoseDifference(r.PhantomToReference, plus, mm, deg);
    const bool within = mm <= parser.GetDouble("tolerance-mm") && deg <= parser.GetDouble("tolerance-deg");
    doc["comparison"] = {{"file", parser.Get("compare")}, {"translationMm", mm}, {"rotationDeg", deg},
                         {"plusErrorMm", plusError}, {"within", within}};
    if (!parser.Json())
      out << "against " << parser.Get("compare") << ": " << mm << " mm, " << deg << " deg (PLUS's error figure "
          << plusError << " mm): " << (within ? "within" : "OUTSIDE") << " the tolerance\n";
    if (!within) code = 1;
  }
  if (parser.Has("out")) {
    std::string error;
    if (!WriteConfigurationWith(parser.Get("plus-config"), parser.Get("out"), config.PhantomFrame, config.ReferenceFrame,
                                r.PhantomToReference, r.PlusErrorMm, error)) {
      err << "roboplan phantom-registration: " << error << "\n";
      return 1;
    }
    if (!parser.Json()) out << "wrote " << parser.Get("out") << "\n";
  }
  if (parser.Json()) out << doc.dump(2) << "\n";
  return code;
}

}  // namespace rp
