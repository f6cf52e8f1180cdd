#include "rpVolumesCommands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>


#include "rpArgParser.h"
#include "rpDicomTransferSyntax.h"
#include "rpNodeStorage.h"
#include "rpKneePhantom.h"
#include "rpProgress.h"
#include "rpSceneFormats.h"
#include "rpTransformIO.h"
#include "rpVolumeFiles.h"
#include "rpVolumeIO.h"
#include "rpVolumeRegistration.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPVolumesLogic.h"
#include "rpStrings.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

nlohmann::json MatrixJson(const vtkMatrix4x4* m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < 4; ++c) row.push_back(m->GetElement(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json VolumeJson(const ImageVolume& v) {
  int dims[3];
  v.Image->GetDimensions(dims);
  double spacing[3];
  v.GetSpacing(spacing);
  double range[2];
  v.Image->GetScalarRange(range);
  return {{"dimensions", {dims[0], dims[1], dims[2]}},
          {"spacing", {spacing[0], spacing[1], spacing[2]}},
          {"ijkToRAS", MatrixJson(v.IJKToRAS)},
          {"scalarType", v.Image->GetScalarTypeAsString()},
          {"scalarRange", {range[0], range[1]}},
          {"modality", v.Modality},
          {"window", v.Window},
          {"level", v.Level}};
}

std::string SizeText(const ImageVolume& v) {
  int dims[3];
  v.Image->GetDimensions(dims);
  double spacing[3];
  v.GetSpacing(spacing);
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " voxels, " +
         Fixed(spacing[0], 3) + " x " + Fixed(spacing[1], 3) + " x " + Fixed(spacing[2], 3) + " mm";
}

// Registration progress lines without the per-iteration metric (one line per percent).
ProgressCallback Quieter(TerminalProgress& progress) {
  return [&progress](double f, const std::string& m) { progress.Report(f, m.substr(0, m.find(" MI "))); };
}

}  // namespace

// ---------------------------------------------------------------------------------------------
namespace {

// The image stack a segmentation object lies on, as `roboplan dicom` names it: "<ID> (CT
// "description")", or why there is none.
std::string ReferenceText(const DicomScanResult& scan, const DicomSegmentationObjectInfo& object) {
  if (object.ReferencedSeriesUID.empty()) return "names no image series";
  for (const auto& s : scan.Series)
    if (s.SeriesInstanceUID == object.ReferencedSeriesUID)
      return "on " + s.StackID + " (" + (s.Modality.empty() ? "??" : s.Modality) + " \"" + s.SeriesDescription + "\")";
  return "on " + object.ReferencedSeriesUID + " (not in this folder)";
}

nlohmann::json ScanJson(const DicomScanResult& scan) {
  nlohmann::json doc;
  doc["ok"] = !scan.Series.empty() || !scan.Segmentations.empty();
  doc["filesExamined"] = scan.FilesExamined;
  doc["nonDicomFiles"] = scan.NonDicomFiles;
  doc["nonImageDicomFiles"] = scan.NonImageDicomFiles;
  doc["corruptFiles"] = scan.CorruptFiles;
  doc["series"] = nlohmann::json::array();
  for (const auto& s : scan.Series) {
    doc["series"].push_back({{"id", s.StackID},
                             {"seriesInstanceUID", s.SeriesInstanceUID},
                             {"stack", s.StackIndex},
                             {"stacks", s.StackCount},
                             {"orientation", s.OrientationName},
                             {"imageOrientationPatient", std::vector<double>(s.Orientation, s.Orientation + 6)},
                             {"studyInstanceUID", s.StudyInstanceUID},
                             {"modality", s.Modality},
                             {"description", s.SeriesDescription},
                             {"seriesNumber", s.SeriesNumber},
                             {"patientName", s.PatientName},
                             {"size", {s.Columns, s.Rows, s.Slices}},
                             {"spacing", {s.PixelSpacing[1], s.PixelSpacing[0], s.SliceSpacing}},
                             {"transferSyntaxUID", s.TransferSyntaxUID},
                             {"transferSyntax", TransferSyntaxLabel(s.TransferSyntaxUID)},
                             {"files", s.Files.size()},
                             {"loadable", s.Problem.empty()},
                             {"problem", s.Problem},
                             {"warnings", s.Warnings}});
  }
  doc["segmentations"] = nlohmann::json::array();
  for (const auto& o : scan.Segmentations) {
    const bool present = std::any_of(scan.Series.begin(), scan.Series.end(), [&](const DicomSeriesInfo& s) {
      return !o.ReferencedSeriesUID.empty() && s.SeriesInstanceUID == o.ReferencedSeriesUID;
    });
    doc["segmentations"].push_back({{"id", o.SeriesInstanceUID},
                                    {"kind", o.Kind},
                                    {"file", o.File},
                                    {"description", o.SeriesDescription},
                                    {"seriesNumber", o.SeriesNumber},
                                    {"segments", o.Segments},
                                    {"referencedSeriesInstanceUID", o.ReferencedSeriesUID},
                                    {"referencedSeriesPresent", present},
                                    {"frameOfReferenceUID", o.FrameOfReferenceUID},
                                    {"transferSyntaxUID", o.TransferSyntaxUID},
                                    {"transferSyntax", TransferSyntaxLabel(o.TransferSyntaxUID)}});
  }
  return doc;
}

void ReportScanText(const DicomScanResult& scan, const std::string& folder, std::ostream& out) {
  out << scan.Series.size() << " series";
  if (!scan.Segmentations.empty()) out << " and " << scan.Segmentations.size() << " segmentation object(s)";
  out << " in " << folder << " (" << scan.FilesExamined << " files examined, " << scan.NonDicomFiles << " not DICOM, "
      << scan.NonImageDicomFiles << " DICOM without images, " << scan.CorruptFiles.size() << " corrupt)\n";
  int index = 1;
  for (const auto& s : scan.Series) {
    out << "  " << index++ << ". " << (s.Modality.empty() ? "??" : s.Modality) << "  \"" << s.SeriesDescription
        << "\"  " << s.OrientationName << "  " << s.Columns << "x" << s.Rows << "x" << s.Slices << "  "
        << Fixed(s.PixelSpacing[1], 3) << " x " << Fixed(s.PixelSpacing[0], 3) << " x " << Fixed(s.SliceSpacing, 3) << " mm\n     "
        << s.StackID
        << (s.StackCount > 1 ? "  (stack " + std::to_string(s.StackIndex) + " of " + std::to_string(s.StackCount) +
                                   " in this series)"
                             : std::string())
        << "\n     " << TransferSyntaxLabel(s.TransferSyntaxUID) << "\n";
    if (!s.Problem.empty()) out << "     cannot load as is: " << s.Problem << "\n";
    for (const auto& w : s.Warnings) out << "     warning: " << w << "\n";
  }
  for (const auto& o : scan.Segmentations) {
    std::string segments;
    for (const auto& name : o.Segments) segments += (segments.empty() ? "" : ", ") + name;
    out << "  " << index++ << ". " << o.Kind << "  \"" << o.SeriesDescription << "\"  " << o.Segments.size()
        << (o.Kind == "SEG" ? " segment(s)" : " ROI(s)") << (segments.empty() ? "" : ": " + segments) << "\n     "
        << o.SeriesInstanceUID << "  " << ReferenceText(scan, o) << "\n     " << TransferSyntaxLabel(o.TransferSyntaxUID)
        << "\n";
  }
  for (const auto& c : scan.CorruptFiles) out << "  corrupt: " << c << "\n";
}

}  // namespace

int RunDicomCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("dicom",
                   "List what a DICOM folder (searched recursively) or DICOMDIR holds: the image series "
                   "(ID, modality, description, orientation, size, spacing, transfer syntax, and why a "
                   "series cannot be loaded) and the segmentations (DICOM SEG and RTSTRUCT: segments, and the "
                   "image series each lies on). A series holding several stacks (orientations or image "
                   "sizes, e.g. a three-plane localizer) is listed stack by stack, each with its own ID "
                   "(<SeriesInstanceUID>#<n>) for `--series`; a segmentation's ID is its SeriesInstanceUID. "
                   "Non-DICOM files are skipped and counted; corrupt files are named.");
  parser.Positional("folder", "folder, DICOMDIR or single DICOM file");
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  TerminalProgress progress("dicom", parser.Json(), err);
  DicomScanResult scan;
  std::string error;
  vtkNew<vtkRPVolumesLogic> logic;
  if (!logic->ScanDicomFolder(parser.Get("folder"), scan, error, progress.Callback())) {
    err << "roboplan dicom: " << error << "\n";
    return 1;
  }
  if (parser.Json())
    out << ScanJson(scan).dump(2) << "\n";
  else
    ReportScanText(scan, parser.Get("folder"), out);
  if (scan.Series.empty() && scan.Segmentations.empty()) {
    err << "roboplan dicom: no DICOM image series or segmentation in " << parser.Get("folder") << "\n";
    return 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
namespace {

SegmentationConversionRequest SegmentationRequest(const ArgParser& parser) {
  SegmentationConversionRequest request;
  request.In = parser.Get("in");
  request.Out = parser.Get("out");
  request.Series = parser.Get("series");
  request.Reference = parser.Get("reference");
  request.InputKind = parser.Get("input-kind");
  request.Labels = parser.Get("labels");
  request.ResampleIrregularSpacing = parser.Has("resample-irregular");
  return request;
}

int ReportSegmentationConversion(const ArgParser& parser, const SegmentationConversion& c, std::ostream& out,
                                 std::ostream& err) {
  if (c.FailureCode != 0) {
    err << "roboplan convert: " << c.Error << "\n";
    return c.FailureCode;
  }
  for (const auto& w : c.Warnings) err << "roboplan convert: warning: " << w << "\n";
  const bool intoFile = c.OutputFormat == "segmentation file";
  if (parser.Json()) {
    nlohmann::json doc = {{"ok", true},       {"input", parser.Get("in")}, {"output", parser.Get("out")},
                          {"segments", c.Segments}, {"outputFormat", c.OutputFormat}, {"warnings", c.Warnings}};
    if (intoFile) {
      doc["segmentNames"] = c.SegmentNames;
      doc["inputKind"] = c.InputKind;
      if (!c.InputKindReason.empty()) doc["inputKindReason"] = c.InputKindReason;
    }
    out << doc.dump(2) << "\n";
  } else {
    out << "wrote " << parser.Get("out") << " (" << c.Segments << " segments"
        << (c.InputKindReason.empty() ? "" : " from a " + c.InputKindReason) << ")\n";
  }
  return 0;
}

}  // namespace

int RunConvertCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("convert",
                   "Convert a volume between DICOM series (folder, DICOMDIR or file), NRRD (.nrrd/.nhdr), "
                   "NIfTI (.nii/.nii.gz) and MetaImage (.mha/.mhd). An output name without one of those "
                   "extensions is a folder that receives a DICOM series (CT or MR Image Storage). "
                   "Geometry (IJK-to-RAS, direction cosines) and voxel values are kept. "
                   "Scenes convert between RoboPlan's .rpscene and 3D Slicer's .mrml and .mrb the same way. "
                   "Segmentations: an output named .seg.nrrd receives a segmentation: a DICOM SEG or RTSTRUCT (file, "
                   "or the one a DICOM folder holds, on the image series it references), or a labelmap volume (one "
                   "segment per label value, named and coloured by --labels); a .seg.nrrd converts to a DICOM SEG (a "
                   ".dcm file, or a folder) with --reference, the image series it segments. From a DICOM folder "
                   "holding a series and its segmentation, a volume output takes the series.");
  parser.Positional("in", "input volume or DICOM folder, or scene (.rpscene, .mrml, .mrb), or DICOM SEG/RTSTRUCT, or "
                          "labelmap")
      .Positional("out", "output volume file, or a folder for a DICOM series, or scene, or segmentation (.seg.nrrd)")
      .Option("series", "id",
              "DICOM input: the series to convert when there are several: its SeriesInstanceUID, or "
              "<SeriesInstanceUID>#<n> for one stack of a series that holds several, or a SEG's or RTSTRUCT's "
              "SeriesInstanceUID (see `roboplan dicom`)")
      .Option("modality", "CT|MR", "DICOM output: the modality (default: the input's, else CT)")
      .Flag("resample-irregular",
            "DICOM input: load a series with a missing slice or uneven spacing by resampling it onto a "
            "regular grid along the slice normal (refused otherwise)")
      .Option("reference", "folder",
              "segmentations: the DICOM image series a SEG or RTSTRUCT refers to (its grid; needed to write a SEG, "
              "optional to read one: without it a SEG keeps the grid its frames span, an RTSTRUCT looks in its own "
              "folder)")
      .Option("input-kind", "auto|labelmap|intensity",
              "into a .seg.nrrd: whether a volume input is a labelmap (auto: whole numbers >= 0 with at most 1000 "
              "distinct values are labels; an intensity image does not convert)",
              "auto")
      .Option("labels", "file",
              "into a .seg.nrrd from a labelmap: label names and colours: Slicer colour table (.ctbl/.txt), ITK-SNAP "
              "label file, or a .seg.nrrd (its segments' names, colours and tissue classes)");
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  vtkNew<vtkRPVolumesLogic> logic;
  if (IsSceneFileName(parser.Get("in")) || IsSceneFileName(parser.Get("out")))
    return ReportSceneConversion(logic->ConvertScene(parser.Get("in"), parser.Get("out")), parser.Get("in"),
                                 parser.Get("out"), parser.Json(), out, err);
  const SegmentationConversion segmentation = logic->ConvertSegmentation(SegmentationRequest(parser));
  if (segmentation.Applies) return ReportSegmentationConversion(parser, segmentation, out, err);
  const std::string modality = parser.Get("modality");
  if (!modality.empty() && modality != "CT" && modality != "MR") {
    err << "roboplan convert: --modality must be CT or MR\n";
    return 2;
  }
  TerminalProgress progress("convert", parser.Json(), err);
  VolumeReadOptions readOptions;
  readOptions.SeriesInstanceUID = parser.Get("series");
  readOptions.Dicom.ResampleIrregularSpacing = parser.Has("resample-irregular");
  ImageVolume volume;
  std::vector<std::string> warnings;
  std::string error;
  if (!logic->ConvertVolume(parser.Get("in"), parser.Get("out"), readOptions, modality, volume, warnings, error,
                            progress.Callback())) {
    err << "roboplan convert: " << error << "\n";
    return 1;
  }
  if (parser.Json()) {
    nlohmann::json doc = VolumeJson(volume);
    doc["ok"] = true;
    doc["input"] = parser.Get("in");
    doc["output"] = parser.Get("out");
    doc["outputFormat"] = IsVolumeFileName(parser.Get("out")) ? "volume file" : "DICOM series";
    doc["warnings"] = warnings;
    out << doc.dump(2) << "\n";
  } else {
    for (const auto& w : warnings) err << "roboplan convert: warning: " << w << "\n";
    out << "wrote " << parser.Get("out") << " (" << SizeText(volume) << ")\n";
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
int RunPhantomCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("phantom",
                   "Write the built-in knee phantom (the Visible Human Female's right knee, or analytic solids "
                   "with --anatomy analytic): <out>/CT and <out>/MR as DICOM series (the MR is a "
                   "proton-density-like volume with 1.7 mm slices, in another pose), <out>/labels.nrrd "
                   "(ground-truth labelmap on the CT grid), <out>/surfaces/*.vtp (the true surfaces, real "
                   "anatomy only), <out>/MRToCT-truth.tfm (the true transform that puts the MR onto the CT: "
                   "ITK LPS 'from parent', as Slicer writes it) and <out>/phantom.json (tissues, labels, HU, "
                   "the CT-to-MR matrix).");
  parser.Option("out", "dir", "output folder (created)")
      .Option("size", "small|demo|full",
              "small: CT 96x96x64 (tests); demo: 192x192x128 (the demo); full: 512x512x300 (benchmarks)", "small")
      .Option("anatomy", "real|analytic", "the real knee's surfaces or analytic solids with closed-form distances",
              "real")
      .Option("seed", "n", "noise seed (same seed, same volumes)", "1")
      .Option("format", "dicom|nrrd", "volume format of CT and MR", "dicom");
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  const std::string dir = parser.Get("out"), size = parser.Get("size"), format = parser.Get("format");
  if (dir.empty()) {
    err << "roboplan phantom: --out <dir> is required\n";
    return 2;
  }
  if (size != "small" && size != "demo" && size != "full") {
    err << "roboplan phantom: --size must be small, demo or full, not '" << size << "'\n";
    return 2;
  }
  const std::string anatomy = parser.Get("anatomy");
  if (anatomy != "real" && anatomy != "analytic") {
    err << "roboplan phantom: --anatomy must be real or analytic, not '" << anatomy << "'\n";
    return 2;
  }
  if (format != "dicom" && format != "nrrd") {
    err << "roboplan phantom: --format must be dicom or nrrd\n";
    return 2;
  }
  KneePhantomOptions options;
  options.Size = size == "full" ? KneePhantomSize::Full : size == "demo" ? KneePhantomSize::Demo : KneePhantomSize::Small;
  options.Anatomy = anatomy == "analytic" ? KneeAnatomy::Analytic : KneeAnatomy::Real;
  try {
    const long seed = parser.GetInt("seed");
    if (seed < 0 || seed > 0xffffffffL) throw std::invalid_argument("--seed must be in 0..4294967295");
    options.Seed = static_cast<uint32_t>(seed);
  } catch (const std::invalid_argument& e) {
    err << "roboplan phantom: " << e.what() << "\n";
    return 2;
  }
  TerminalProgress progress("phantom", parser.Json(), err);
  const auto start = std::chrono::steady_clock::now();
  vtkNew<vtkRPVolumesLogic> logic;
  vtkRPVolumesLogic::KneePhantomFiles files;
  std::string error;
  if (!logic->WriteKneePhantom(options, dir, format == "dicom", files, error, progress.Callback())) {
    err << "roboplan phantom: " << error << "\n";
    return 1;
  }
  const KneePhantom& phantom = files.Phantom;
  const fs::path root(dir);
  const std::string& ctPath = files.CT;
  const std::string& mrPath = files.MR;
  nlohmann::json surfaces = nlohmann::json::object();
  for (const auto& [name, path] : files.Surfaces) surfaces[name] = path;
  nlohmann::json doc;
  doc["ok"] = true;
  doc["size"] = size;
  doc["anatomy"] = phantom.Model->Description();
  doc["surfaces"] = surfaces;
  doc["seed"] = options.Seed;
  doc["ct"] = VolumeJson(phantom.CT);
  doc["ct"]["path"] = ctPath;
  doc["mr"] = VolumeJson(phantom.MR);
  doc["mr"]["path"] = mrPath;
  doc["labels"] = VolumeJson(phantom.Labels);
  doc["labels"]["path"] = files.Labels;
  doc["ctToMR"] = MatrixJson(phantom.CTToMR);
  doc["mrToCTTransformFile"] = files.TruthTransform;
  doc["tissues"] = nlohmann::json::array();
  for (const auto& t : KneeTissues())
    doc["tissues"].push_back({{"label", t.Label},
                              {"name", t.Name},
                              {"class", t.Class},
                              {"ctHU", t.CTHounsfield},
                              {"mrIntensity", t.MRIntensity},
                              {"color", t.Color}});
  doc["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  {
    std::ofstream file(root / "phantom.json");
    file << doc.dump(2) << "\n";
    if (!file) {
      err << "roboplan phantom: cannot write " << (root / "phantom.json").string() << "\n";
      return 1;
    }
  }
  if (parser.Json()) {
    out << doc.dump(2) << "\n";
  } else {
    out << "knee phantom (" << size << ") written to " << dir << "\n  CT: " << ctPath << " (" << SizeText(phantom.CT)
        << ")\n  MR: " << mrPath << " (" << SizeText(phantom.MR) << ")\n  labels: labels.nrrd, truth: MRToCT-truth.tfm, "
        << "phantom.json\n";
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// register-volumes in three parts: parse the options -> run (read, register, score, write) -> report.
namespace {

struct RegisterVolumesRequest {
  std::string Fixed, Moving, Out, Initial, Truth;  // Initial, Truth: empty when not given
  bool Centre = false;
  RigidRegistrationOptions Options;
};

struct RegisterVolumesRun {
  ImageVolume Fixed;  // the fixed volume's node, as a volume (for --truth)
  RigidRegistrationResult Result;
  double TruthRMS = -1.0;
  bool Written = false;
};

void DeclareRegisterVolumesOptions(ArgParser& parser) {
  const auto volumeFiles = ExtensionsForNodeClass("vtkRPScalarVolumeNode");
  const auto transformFiles = ExtensionsForNodeClass("vtkRPLinearTransformNode");
  parser.Positional("fixed", "fixed volume (file or DICOM folder)")
      .Input(FileKind::Image, volumeFiles)
      .Positional("moving", "moving volume (file or DICOM folder)")
      .Input(FileKind::Image, volumeFiles)
      .Option("out", "transform", "transform file to write (.tfm, .txt, .h5)")
      .Output(FileKind::Transform, transformFiles)
      .Required()
      .Option("initial", "transform", "start from this MovingToFixed transform file (default: identity)")
      .Input(FileKind::Transform, transformFiles)
      .Flag("centre", "start by aligning the volumes' geometric centres (ignored with --initial)")
      .Option("levels", "f1,f2,...", "shrink factor per resolution level (smoothing 0.75 f mm)", "8,4,2,1")
      .Integers()
      .AtLeast(1)
      .AtMost(64)
      .Option("iterations", "n", "maximum iterations per level", "200")
      .Integer()
      .AtLeast(1)
      .AtMost(100000)
      .Option("sampling", "fraction", "fraction of fixed voxels sampled by the metric", "0.1")
      .Number()
      .GreaterThan(0)
      .AtMost(1)
      .Option("bins", "n", "histogram bins of the mutual information", "32")
      .Integer()
      .AtLeast(5)
      .AtMost(1024)
      .Option("truth", "transform",
              "a known MovingToFixed transform file (e.g. the phantom's MRToCT-truth.tfm): report the RMS "
              "difference over the fixed volume's central region")
      .Input(FileKind::Transform, transformFiles);
}

// Types and ranges were checked by the parser (declared above).
RegisterVolumesRequest ParseRegisterVolumesRequest(const ArgParser& parser) {
  RegisterVolumesRequest request;
  request.Fixed = parser.Get("fixed");
  request.Moving = parser.Get("moving");
  request.Out = parser.Get("out");
  if (parser.Has("initial")) request.Initial = parser.Get("initial");
  if (parser.Has("truth")) request.Truth = parser.Get("truth");
  request.Centre = parser.Has("centre");
  RigidRegistrationOptions& options = request.Options;
  options.ShrinkFactors.clear();
  options.SmoothingSigmasMM.clear();
  for (double f : parser.GetDoubles("levels")) options.ShrinkFactors.push_back(static_cast<unsigned>(f));
  options.MaxIterationsPerLevel = static_cast<unsigned>(parser.GetInt("iterations"));
  options.HistogramBins = static_cast<unsigned>(parser.GetInt("bins"));
  options.SamplingFraction = parser.GetDouble("sampling");
  return request;
}

// RMS difference to a known transform over a 5x5x5 grid spanning the central half of the fixed volume.
double TruthRMSOverCentre(const ImageVolume& fixed, const vtkMatrix4x4* movingToFixed, vtkMatrix4x4* truth) {
  int dims[3];
  fixed.Image->GetDimensions(dims);
  std::vector<std::array<double, 3>> points;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      for (int c = 0; c < 5; ++c) {
        const double ijk[3] = {(0.25 + 0.125 * a) * (dims[0] - 1), (0.25 + 0.125 * b) * (dims[1] - 1),
                               (0.25 + 0.125 * c) * (dims[2] - 1)};
        std::array<double, 3> ras;
        fixed.IndexToRAS(ijk, ras.data());
        points.push_back(ras);
      }
  return TransformRMSDifference(movingToFixed, truth, points);
}

// Reads and registers through the Volumes logic (as a host's scene would: the moving volume under
// the MovingToFixed transform), scores against --truth and writes --out (only when converged).
// False: an input could not be read or the registration could not run (named on `err`).
bool RunRegisterVolumes(RegisterVolumesRequest& request, RegisterVolumesRun& run, TerminalProgress& progress,
                        std::ostream& err) {
  RigidRegistrationOptions& options = request.Options;
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  std::string error;
  vtkRPScalarVolumeNode* fixed = logic->LoadVolume(request.Fixed, "", error);
  vtkRPScalarVolumeNode* moving = fixed ? logic->LoadVolume(request.Moving, "", error) : nullptr;
  if (!moving) {
    err << "roboplan register-volumes: " << error << "\n";
    return false;
  }
  run.Fixed = FromNode(fixed);
  for (unsigned f : options.ShrinkFactors) options.SmoothingSigmasMM.push_back(f > 1 ? 0.75 * f : 0.0);
  if (!request.Initial.empty()) {
    vtkNew<vtkMatrix4x4> movingToFixed;
    if (!ReadTransformFile(request.Initial, movingToFixed, error)) {
      err << "roboplan register-volumes: " << error << "\n";
      return false;
    }
    options.InitialFixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();
    vtkMatrix4x4::Invert(movingToFixed, options.InitialFixedToMoving);
  } else {
    options.InitializeByGeometryCentres = request.Centre;
  }
  vtkNew<vtkMatrix4x4> truth;
  if (!request.Truth.empty() && !ReadTransformFile(request.Truth, truth, error)) {
    err << "roboplan register-volumes: " << error << "\n";
    return false;
  }
  RigidRegistrationResult& result = run.Result;
  // Not converged: the logic applies nothing, but the optimizer ran (StopReason) and is reported.
  if (!logic->RegisterVolumes(fixed, moving, options, result, error, Quieter(progress)) && result.StopReason.empty()) {
    err << "roboplan register-volumes: " << error << "\n";
    return false;
  }
  if (!request.Truth.empty()) run.TruthRMS = TruthRMSOverCentre(run.Fixed, result.MovingToFixed, truth);
  if (result.Converged) {
    run.Written = WriteTransformFile(request.Out, result.MovingToFixed, error);
    if (!run.Written) err << "roboplan register-volumes: " << error << "\n";
  } else {
    err << "roboplan register-volumes: did not converge (" << result.StopReason << "); " << request.Out
        << " not written\n";
  }
  return true;
}

void ReportRegisterVolumes(const RegisterVolumesRequest& request, const RegisterVolumesRun& run, bool json,
                           std::ostream& out) {
  const RigidRegistrationResult& result = run.Result;
  const bool haveTruth = !request.Truth.empty();
  if (json) {
    nlohmann::json doc;
    doc["ok"] = result.Converged && run.Written;
    doc["converged"] = result.Converged;
    doc["stopReason"] = result.StopReason;
    doc["finalMetric"] = result.FinalMetric;
    doc["iterations"] = result.Iterations;
    doc["seconds"] = result.Seconds;
    doc["movingToFixed"] = MatrixJson(result.MovingToFixed);
    doc["output"] = run.Written ? nlohmann::json(request.Out) : nlohmann::json();
    if (haveTruth) doc["rmsToTruthMM"] = run.TruthRMS;
    out << doc.dump(2) << "\n";
  } else if (result.Converged) {
    out << "converged in " << result.Iterations << " iterations, " << Fixed(result.Seconds, 2) << " s, MI "
        << Fixed(result.FinalMetric, 4) << (run.Written ? "; wrote " + request.Out : std::string()) << "\n";
    if (haveTruth)
      out << "RMS difference to the truth (central region of the fixed volume): " << Fixed(run.TruthRMS, 3) << " mm\n";
  }
}

}  // namespace

int RunRegisterVolumesCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser(
      "register-volumes",
      "Rigid registration of a moving volume (e.g. MR) onto a fixed one (e.g. CT) by Mattes mutual "
      "information (ITK v4, versor rigid, multi-resolution). Writes the transform that puts the moving "
      "volume onto the fixed one (its 'to parent', MovingToFixed) as an ITK transform file (LPS, 'from "
      "parent', as Slicer). When the optimizer does not converge the command exits 1 and does not "
      "write --out.");
  DeclareRegisterVolumesOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  RegisterVolumesRequest request = ParseRegisterVolumesRequest(parser);
  TerminalProgress progress("register", parser.Json(), err);
  RegisterVolumesRun run;
  if (!RunRegisterVolumes(request, run, progress, err)) return 1;
  ReportRegisterVolumes(request, run, parser.Json(), out);
  return run.Result.Converged && run.Written ? 0 : 1;
}

}  // namespace rp
