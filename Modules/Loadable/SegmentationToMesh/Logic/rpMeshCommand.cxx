#include "rpMeshCommand.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <future>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "rpArgParser.h"
#include "rpBoneSplit.h"
#include "rpDataLoader.h"
#include "rpImageVolume.h"
#include "rpLabelComparison.h"
#include "rpLabelmapInput.h"
#include "rpModelIO.h"
#include "rpNodeStorage.h"
#include "rpProgress.h"
#include "rpSegmentationEditor.h"
#include "rpSegmentationIO.h"
#include "rpSegmentationToModels.h"
#include "rpVolumeIO.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct BadArgument : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

std::array<double, 3> ParsePoint(const std::string& text, const std::string& option) {
  std::array<double, 3> p{};
  std::stringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n >= 3) throw BadArgument("--" + option + " '" + text + "': expected x,y,z");
    try {
      size_t used = 0;
      p[static_cast<size_t>(n)] = std::stod(part, &used);
      if (used != part.size()) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw BadArgument("--" + option + " '" + text + "': '" + part + "' is not a number");
    }
    ++n;
  }
  if (n != 3) throw BadArgument("--" + option + " '" + text + "': expected x,y,z (RAS, mm)");
  return p;
}

json StatsJson(const MeshStats& s) {
  return {{"triangles", s.Triangles},
          {"points", s.Points},
          {"labelVoxels", s.LabelVoxels},
          {"labelVolumeMm3", s.LabelVolumeMm3},
          {"meshVolumeMm3", s.MeshVolumeMm3},
          {"volumeErrorPercent", s.VolumeErrorPercent},
          {"areaMm2", s.AreaMm2},
          {"volumeCorrectionMm", s.VolumeCorrectionMm},
          {"boundaryEdges", s.BoundaryEdges},
          {"nonManifoldEdges", s.NonManifoldEdges},
          {"watertight", s.Watertight},
          {"nonManifoldVertices", s.NonManifoldVertices},
          {"manifold", s.Manifold},
          {"method", s.Method},
          {"maxDeviationMm", s.MaxDeviationMm},
          {"budgetTriangles", s.BudgetTriangles},
          {"withinBudget", s.WithinBudget},
          {"droppedComponents", s.DroppedComponents},
          {"droppedVolumeMm3", s.DroppedVolumeMm3},
          {"touchesBorder", s.TouchesBorder},
          {"gridStep", {s.GridStep[0], s.GridStep[1], s.GridStep[2]}},
          {"seconds", s.Seconds},
          {"warnings", s.Warnings}};
}

// Volumes and segmentations: what `mesh` reads (from the storages' registrations).
std::vector<std::string> InputExtensions() {
  auto extensions = ExtensionsForNodeClass("vtkRPSegmentationNode");
  for (const auto& ext : ExtensionsForNodeClass("vtkRPScalarVolumeNode")) extensions.push_back(ext);
  return extensions;
}

// Model file formats, from the model storage's registration (rpModelIO): "vtp", "vtk", ...
std::vector<std::string> ModelFormats() {
  std::vector<std::string> formats;
  for (const auto& storage : GetNodeStorages()) {
    if (storage->NodeClassForFiles() != "vtkRPModelNode") continue;
    for (const auto& extension : storage->Extensions()) formats.push_back(extension.substr(1));
  }
  return formats;
}

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : separator) + item;
  return text;
}

std::string SafeFileName(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return name.empty() ? "segment" : name;
}

// 1. Parse: what the command was asked (the options' values the steps below read from the
// parser directly are checked there too).
struct MeshRequest {
  ModelBuildOptions Build;
  std::string Method, Format;
  std::vector<std::array<double, 3>> Seeds;
  double Multiplier = 2.5, MaxFraction = 0.9;
  int Iterations = 3, Radius = 2, Split = 0;
  InputKind Kind = InputKind::Auto;
};

// 2. Run: the scene's nodes and what each step made, for the report.
struct MeshRun {
  std::string Input;
  fs::path OutDir;
  vtkRPScene* Scene = nullptr;
  std::string Error;
  vtkRPNode* Loaded = nullptr;
  vtkRPSegmentationNode* Segmentation = nullptr;
  json SegmentationSteps = json::array();
  json InputInfo = {{"kind", "segmentation"}, {"reason", "a segmentation file"}};
  json BoneSplit, TruthScores, Segments = json::array();
  std::vector<SegmentModels> Models;
  int Failures = 0;
};

void DeclareOptions(ArgParser& parser) {
  parser.Positional("input", "volume or labelmap (.nrrd, .nii.gz, .mha, DICOM folder or DICOMDIR) or segmentation (.seg.nrrd, DICOM SEG or RTSTRUCT file or folder)")
      .Input(FileKind::Image, InputExtensions())
      .Option("series", "id",
              "DICOM input: the series to mesh when there are several: its SeriesInstanceUID, or "
              "<SeriesInstanceUID>#<n> for one stack of a series that holds several (see `roboplan dicom`)")
      .Flag("resample-irregular",
            "DICOM input: load a series with a missing slice or uneven spacing by resampling it onto a "
            "regular grid along the slice normal (refused otherwise)")
      .Option("out", "dir", "output folder (created)")
      .OutputFolder()
      .Required()
      .Option("input-kind", "auto|labelmap|intensity",
              "a volume file is a labelmap (one segment per label value) or an intensity image to segment; auto: "
              "a labelmap when no threshold option is given, the voxels are few whole numbers >= 0 and --labels is "
              "given or the file is named *-label.*, *_label.*, *labelmap*, *.seg.*",
              "auto")
      .OneOf()
      .Option("labels", "file", "label names and colours: Slicer colour table (.ctbl/.txt) or ITK-SNAP label file")
      .Input(FileKind::Any)
      .Option("method", "threshold|region-grow|confidence", "segmentation method for volumes", "threshold")
      .OneOf()
      .Option("preset", "bone|cortical|soft-tissue|fat", "tissue preset(s), repeatable (several tissues)", "bone")
      .OneOf()
      .Repeatable()
      .Option("lower", "HU", "lower threshold (overrides the preset; one tissue)")
      .Number()
      .Option("upper", "HU", "upper threshold (overrides the preset; one tissue)")
      .Number()
      .Option("seed", "x,y,z", "seed point in RAS mm (repeatable): region growing, confidence, --keep-at-seed")
      .Point()
      .Repeatable()
      .Option("multiplier", "k", "confidence connected: mean ± k·sigma", "2.5")
      .Number()
      .GreaterThan(0)
      .Option("iterations", "n", "confidence connected iterations", "3")
      .Integer()
      .AtLeast(0)
      .Option("radius", "voxels", "confidence connected initial neighbourhood radius", "2")
      .Integer()
      .AtLeast(0)
      .Option("closing", "mm", "morphological closing radius")
      .Number()
      .AtLeast(0)
      .Option("opening", "mm", "morphological opening radius")
      .Number()
      .AtLeast(0)
      .Flag("fill-holes", "fill enclosed holes")
      .Flag("keep-largest", "keep the largest connected component")
      .Flag("keep-at-seed", "keep the component at the first seed")
      .Flag("split-bones", "bones one by one from a CT: one segment per bone, touching bones split, table and "
                           "specks dropped, knee bones named (femur, tibia, fibula, patella), others \"Bone N\"")
      .Option("bone-seed", "R,A,S[:name]", "a point on a bone (RAS mm) naming it, or forcing a split (repeatable)")
      .Repeatable()
      .Option("min-bone-ml", "ml", "--split-bones: drop pieces smaller than this", "0.3")
      .Number()
      .AtLeast(0)
      .Option("truth", "labelmap", "score each segment against this labelmap (Dice, surface distance)")
      .Input(FileKind::LabelMap)
      .Option("split", "n", "split into up to n segments, one per component")
      .Integer()
      .AtLeast(1)
      .Option("max-fraction", "f", "refuse a segment covering more than this fraction of the volume (leak)", "0.9")
      .Number()
      .GreaterThan(0)
      .AtMost(1)
      .Option("segment", "id", "mesh only these segments (repeatable)")
      .Repeatable()
      .Option("mesh-method", "gaussian|sinc|slicer|discrete", "surface method", "gaussian")
      .OneOf()
      .Option("smoothing", "sigma", "gaussian smoothing sigma in voxels", "1.0")
      .Number()
      .AtLeast(0)
      .Option("passband", "f", "windowed sinc pass band (sinc, slicer)", "0.01")
      .Number()
      .GreaterThan(0)
      .AtMost(2)
      .Option("sinc-iterations", "n", "windowed sinc iterations (sinc, slicer)", "20")
      .Integer()
      .AtLeast(0)
      .Option("grid-step", "s|sx,sy,sz", "gaussian contour grid step in voxels (>1 = coarser mesh)", "1")
      .Numbers()
      .GreaterThan(0)
      .Option("grid-mm", "mm", "gaussian contour grid spacing in mm (step per axis = max(1, mm / spacing))")
      .Number()
      .GreaterThan(0)
      .Option("decimate", "f", "extra quadric decimation: fraction of triangles removed", "0")
      .Number()
      .AtLeast(0)
      .LessThan(1)
      .Option("triangles", "n", "display mesh: target triangle count")
      .Integer()
      .AtLeast(1)
      .Option("max-error", "mm", "display mesh: max deviation from the full-resolution surface")
      .Number()
      .AtLeast(0)
      .Option("haptic-triangles", "n", "haptic mesh: target triangle count", "20000")
      .Integer()
      .AtLeast(1)
      .Option("haptic-max-error", "mm", "haptic mesh: max deviation from the full-resolution surface")
      .Number()
      .AtLeast(0)
      .Flag("no-haptic", "do not write haptic meshes")
      .Flag("no-volume-correction", "keep the raw surface (no volume correction)")
      .Option("format", Join(ModelFormats(), "|"), "model file format", "vtp")
      .OneOf();
}

// False (after naming the problem on `err`): bad arguments.
bool ParseRequest(const ArgParser& parser, MeshRequest& request, std::ostream& err) {
  ModelBuildOptions& build = request.Build;
  std::string &method = request.Method, &format = request.Format;
  std::vector<std::array<double, 3>>& seeds = request.Seeds;
  double &multiplier = request.Multiplier, &maxFraction = request.MaxFraction;
  int &iterations = request.Iterations, &radius = request.Radius, &split = request.Split;
  InputKind& inputKind = request.Kind;
  try {
    multiplier = parser.GetDouble("multiplier");
    iterations = static_cast<int>(parser.GetInt("iterations"));
    radius = static_cast<int>(parser.GetInt("radius"));
    maxFraction = parser.GetDouble("max-fraction");
    if (parser.Has("split")) split = static_cast<int>(parser.GetInt("split"));
    if (parser.Has("closing")) parser.GetDouble("closing");
    if (parser.Has("opening")) parser.GetDouble("opening");
    if (!parser.Has("out")) throw BadArgument("--out <dir> is required");
    method = parser.Get("method");
    if (method != "threshold" && method != "region-grow" && method != "confidence")
      throw BadArgument("--method '" + method + "': use threshold, region-grow or confidence");
    for (const auto& s : parser.GetAll("seed")) seeds.push_back(ParsePoint(s, "seed"));
    if (!ParseMeshMethod(parser.Get("mesh-method"), build.Display.Method))
      throw BadArgument("--mesh-method '" + parser.Get("mesh-method") + "': use gaussian, sinc, slicer or discrete");
    build.Display.Sigma = parser.GetDouble("smoothing");
    build.Display.SincPassBand = parser.GetDouble("passband");
    build.Display.SincIterations = static_cast<int>(parser.GetInt("sinc-iterations"));
    const auto steps = parser.GetDoubles("grid-step");
    if (steps.size() == 1) {
      for (double& s : build.Display.GridStep) s = steps[0];
    } else if (steps.size() == 3) {
      for (int a = 0; a < 3; ++a) build.Display.GridStep[a] = steps[static_cast<size_t>(a)];
    } else {
      throw BadArgument("--grid-step: one value or three (sx,sy,sz)");
    }
    for (double s : build.Display.GridStep)
      if (!(s > 0)) throw BadArgument("--grid-step must be > 0");
    if (build.Display.Sigma < 0) throw BadArgument("--smoothing must be >= 0");
    if (parser.Has("grid-mm") && !(parser.GetDouble("grid-mm") > 0)) throw BadArgument("--grid-mm must be > 0");
    build.Display.DecimationFraction = parser.GetDouble("decimate");
    if (build.Display.DecimationFraction < 0 || build.Display.DecimationFraction >= 1)
      throw BadArgument("--decimate must be in [0, 1)");
    build.Display.CorrectVolume = !parser.Has("no-volume-correction");
    if (parser.Has("triangles")) build.DisplayLOD.TargetTriangles = parser.GetInt("triangles");
    if (parser.Has("max-error")) build.DisplayLOD.MaxErrorMm = parser.GetDouble("max-error");
    build.Haptic = build.Display;
    build.Haptic.DecimationFraction = 0;
    build.HapticLOD.TargetTriangles = parser.GetInt("haptic-triangles");
    build.HapticLOD.MaxErrorMm = parser.Has("haptic-max-error") ? parser.GetDouble("haptic-max-error") : 0.0;
    build.MakeHaptic = !parser.Has("no-haptic");
    build.SegmentIDs = parser.GetAll("segment");
    format = parser.Get("format");
    const auto formats = ModelFormats();
    if (std::find(formats.begin(), formats.end(), format) == formats.end())
      throw BadArgument("--format '" + format + "': use " + Join(formats, ", "));
    if (parser.Has("keep-at-seed") && seeds.empty()) throw BadArgument("--keep-at-seed needs --seed");
    if (!ParseInputKind(parser.Get("input-kind"), inputKind))
      throw BadArgument("--input-kind '" + parser.Get("input-kind") + "': use auto, labelmap or intensity");
    if ((method == "region-grow" || method == "confidence") && seeds.empty())
      throw BadArgument("--method " + method + " needs at least one --seed x,y,z");
  } catch (const std::exception& e) {
    err << "roboplan mesh: " << e.what() << "\n";
    return false;
  }
  return true;
}

// Each step returns 0 to go on, else the command's exit code (the problem named on `err`).
// The input, through the one loader (a plain labelmap named *.seg.nrrd read as a volume).
int LoadInput(const ArgParser& parser, MeshRun& run, TerminalProgress& progress, std::ostream& err) {
  const std::string& input = run.Input;
  vtkRPScene* scene = run.Scene;
  std::string& error = run.Error;
  vtkRPNode*& loaded = run.Loaded;
  vtkRPSegmentationNode*& segmentation = run.Segmentation;
  progress.Report(0.0, "loading " + input);
  // The one loader (rpDataLoader.h): a volume or segmentation file, a DICOM folder or DICOMDIR.
  ReadOptions read;
  read.Series = parser.Get("series");
  read.ResampleIrregularSpacing = parser.Has("resample-irregular");
  LoadResult load;
  loaded = LoadSingleNode(scene, input, load, read);
  error = load.Error;
  for (const auto& warning : load.Warnings) err << "roboplan mesh: warning: " << warning << "\n";
  if (!loaded && HasExtension(input, ".seg.nrrd")) {
    // A plain labelmap named *.seg.nrrd (no Slicer segment keys): read it as a volume.
    vtkNew<vtkRPScalarVolumeNode> plain;
    std::string volumeError;
    if (ReadVolumeFile(input, plain, volumeError)) {
      plain->SetName(fs::path(input).filename().string());
      scene->AddNode(plain);
      loaded = plain;
    }
  }
  if (!loaded) {
    err << "roboplan mesh: " << error << "\n";
    return 1;
  }
  segmentation = vtkRPSegmentationNode::SafeDownCast(loaded);
  return 0;
}

// A volume that is a labelmap becomes a segmentation (one segment per label value).
int SegmentationFromLabelmap(const ArgParser& parser, const MeshRequest& request, MeshRun& run, bool quiet,
                             std::ostream& err) {
  const std::string& input = run.Input;
  vtkRPScene* scene = run.Scene;
  std::string& error = run.Error;
  vtkRPNode* loaded = run.Loaded;
  vtkRPSegmentationNode*& segmentation = run.Segmentation;
  json& inputInfo = run.InputInfo;
  const InputKind inputKind = request.Kind;
  {
    auto* volume = vtkRPScalarVolumeNode::SafeDownCast(loaded);
    if (!volume) {
      err << "roboplan mesh: '" << input << "' is neither a volume nor a segmentation\n";
      return 1;
    }
    const bool intensityOptions = parser.Has("lower") || parser.Has("upper") || !parser.GetAll("preset").empty() ||
                                  parser.Has("method") || parser.Has("multiplier") || parser.Has("iterations") ||
                                  parser.Has("radius");
    const InputChoice choice =
        ChooseInputKind(inputKind, volume->GetImageData(), input, parser.Has("labels"), intensityOptions);
    inputInfo = {{"kind", choice.Labelmap ? "labelmap" : "intensity"}, {"reason", choice.Reason}};
    // The labelmap hint goes to the error stream even with --json (a run that then finds empty
    // segments would otherwise say only that).
    const bool hint = choice.Reason.find("--input-kind labelmap") != std::string::npos && !choice.Labelmap;
    if (!quiet || hint) err << "input: " << choice.Reason << "\n";
    if (choice.Labelmap) {
      LabelTable table;
      if (parser.Has("labels") && !ReadLabelTable(parser.Get("labels"), table, error)) {
        err << "roboplan mesh: " << error << "\n";
        return 1;
      }
      vtkNew<vtkRPSegmentationNode> created;
      created->SetName(volume->GetName() + " segmentation");
      if (!LabelmapToSegmentation(volume->GetImageData(), volume->GetIJKToRASMatrix(),
                                  parser.Has("labels") ? &table : nullptr, created, error,
                                  choice.Scanned ? &choice.Values : nullptr)) {
        err << "roboplan mesh: '" << input << "': " << error << "\n";
        return 1;
      }
      scene->AddNode(created);
      segmentation = created;
    } else if (parser.Has("labels")) {
      err << "roboplan mesh: --labels names the values of a labelmap, but '" << input
          << "' is taken as an intensity image (" << choice.Reason << ")\n";
      return 2;
    }
  }
  return 0;
}

// --split-bones: the bones of a CT one by one (rp::SplitBones).
int SplitBonesIntoSegments(const ArgParser& parser, const MeshRequest& request, MeshRun& run,
                           TerminalProgress& progress, bool quiet, std::ostream& err) {
  vtkRPScene* scene = run.Scene;
  std::string& error = run.Error;
  vtkRPNode* loaded = run.Loaded;
  vtkRPSegmentationNode*& segmentation = run.Segmentation;
  json& boneSplit = run.BoneSplit;
  const fs::path& outDir = run.OutDir;
  const std::vector<std::array<double, 3>>& seeds = request.Seeds;
  {
    auto* volume = vtkRPScalarVolumeNode::SafeDownCast(loaded);
    BoneSplitOptions options;
    if (parser.Has("lower")) options.LowerHU = parser.GetDouble("lower");
    if (parser.Has("upper")) options.UpperHU = parser.GetDouble("upper");
    options.MinBoneMl = parser.GetDouble("min-bone-ml");
    for (const auto& text : parser.GetAll("bone-seed")) {
      BoneSeed seed;
      if (!ParseBoneSeed(text, seed, error)) {
        err << "roboplan mesh: --bone-seed " << error << "\n";
        return 2;
      }
      options.Seeds.push_back(seed);
    }
    for (const auto& p : seeds) options.Seeds.push_back({p, ""});
    vtkNew<vtkRPSegmentationNode> created;
    created->SetName(volume->GetName() + " bones");
    BoneSplitResult split;
    if (!SplitBones(volume, created, options, split, error,
                    [&](double f, const std::string& m) { progress.Report(0.05 + 0.15 * f, "bones: " + m); })) {
      err << "roboplan mesh: --split-bones: " << error << "\n";
      return 1;
    }
    scene->AddNode(created);
    segmentation = created;
    json bones = json::array();
    for (const auto& b : split.Bones)
      bones.push_back({{"id", b.ID}, {"labelValue", b.LabelValue}, {"volumeMl", b.VolumeMl}, {"namedBy", b.NamedBy},
                       {"centroidRAS", {b.CentroidRAS[0], b.CentroidRAS[1], b.CentroidRAS[2]}}});
    boneSplit = {{"bones", bones}, {"splits", split.Splits}, {"droppedSpecks", split.DroppedSpecks},
                 {"droppedSpecksMl", split.DroppedSpecksMl}, {"droppedOutsideBody", split.DroppedOutsideBody},
                 {"droppedOutsideBodyMl", split.DroppedOutsideBodyMl}, {"notes", split.Notes},
                 {"seconds", split.Seconds}};
    if (!quiet) {
      err << "bones: " << split.Bones.size() << " (" << split.Splits << " touching pair(s) split; dropped "
          << split.DroppedSpecks << " speck(s) and " << split.DroppedOutsideBody
          << " piece(s) outside the body outline)\n";
      for (const auto& b : split.Bones)
        err << "  " << b.ID << ": " << b.VolumeMl << " ml" << (b.NamedBy.empty() ? "" : ", named by " + b.NamedBy)
            << "\n";
      for (const auto& n : split.Notes) err << "  note: " << n << "\n";
    }
    const std::string segPath = (outDir / "segmentation.seg.nrrd").string();
    if (!WriteSegmentationFile(segPath, segmentation, error)) {
      err << "roboplan mesh: " << error << "\n";
      return 1;
    }
  }
  return 0;
}

// An intensity volume: one segment per tissue (presets or one range), then the morphology steps.
int SegmentByThreshold(const ArgParser& parser, const MeshRequest& request, MeshRun& run, TerminalProgress& progress,
                       std::ostream& err) {
  vtkRPScene* scene = run.Scene;
  std::string& error = run.Error;
  vtkRPNode* loaded = run.Loaded;
  vtkRPSegmentationNode*& segmentation = run.Segmentation;
  json& segmentationSteps = run.SegmentationSteps;
  const fs::path& outDir = run.OutDir;
  const std::string& method = request.Method;
  const std::vector<std::array<double, 3>>& seeds = request.Seeds;
  const double multiplier = request.Multiplier, maxFraction = request.MaxFraction;
  const int iterations = request.Iterations, radius = request.Radius, split = request.Split;
  {
    auto* volume = vtkRPScalarVolumeNode::SafeDownCast(loaded);
    vtkNew<vtkRPSegmentationNode> created;
    created->SetName(volume->GetName() + " segmentation");
    scene->AddNode(created);
    segmentation = created;
    // One target per tissue: the presets, or one custom range.
    std::vector<ThresholdPreset> tissues;
    for (const auto& name : parser.GetAll("preset").empty() ? std::vector<std::string>{parser.Get("preset")}
                                                            : parser.GetAll("preset")) {
      const ThresholdPreset* preset = FindThresholdPreset(name);
      if (!preset) {
        err << "roboplan mesh: unknown --preset '" << name << "' (bone, cortical, soft-tissue, fat)\n";
        return 2;
      }
      tissues.push_back(*preset);
    }
    try {
      if (parser.Has("lower") || parser.Has("upper")) {
        if (tissues.size() != 1) {
          err << "roboplan mesh: --lower/--upper apply to one tissue; give at most one --preset\n";
          return 2;
        }
        if (parser.Has("lower")) tissues[0].Lower = parser.GetDouble("lower");
        if (parser.Has("upper")) tissues[0].Upper = parser.GetDouble("upper");
      }
    } catch (const std::exception& e) {
      err << "roboplan mesh: " << e.what() << "\n";
      return 2;
    }
    for (size_t t = 0; t < tissues.size(); ++t) {
      const auto& tissue = tissues[t];
      SegmentTarget target;
      target.ID = tissue.Name;
      target.Name = tissue.Name;
      target.TissueClass = tissue.TissueClass;
      target.Color = tissue.Color;
      target.MaxFraction = maxFraction;
      EditResult result;
      progress.Report(0.05 + 0.1 * t / tissues.size(), "segmenting " + tissue.Name);
      bool ok = false;
      if (method == "threshold") {
        ok = SegmentationEditor::Threshold(volume, segmentation, target, tissue.Lower, tissue.Upper, result, error);
      } else if (method == "region-grow") {
        ok = SegmentationEditor::RegionGrow(volume, segmentation, target, seeds, tissue.Lower, tissue.Upper, result,
                                                error);
      } else {
        ok = SegmentationEditor::ConfidenceConnected(
            volume, segmentation, target, seeds, multiplier, iterations, radius, result, error);
      }
      auto step = [&](const std::string& name, bool stepOk) {
        segmentationSteps.push_back({{"segment", target.ID}, {"step", name}, {"ok", stepOk}, {"voxels", result.Voxels},
                                     {"fraction", result.Fraction}, {"components", result.Components}});
        if (!stepOk) err << "roboplan mesh: " << target.ID << " " << name << ": " << error << "\n";
        return stepOk;
      };
      if (!step(method, ok)) return 1;
      if (parser.Has("closing") &&
          !step("closing", SegmentationEditor::ApplyMorphology(segmentation, target.ID, Morphology::Closing,
                                                                   parser.GetDouble("closing"), result, error)))
        return 1;
      if (parser.Has("opening") &&
          !step("opening", SegmentationEditor::ApplyMorphology(segmentation, target.ID, Morphology::Opening,
                                                                   parser.GetDouble("opening"), result, error)))
        return 1;
      if (parser.Has("fill-holes") &&
          !step("fill-holes", SegmentationEditor::ApplyMorphology(segmentation, target.ID,
                                                                      Morphology::FillHoles, 0, result, error)))
        return 1;
      if (parser.Has("keep-largest") &&
          !step("keep-largest", SegmentationEditor::KeepLargestComponent(segmentation, target.ID, result, error)))
        return 1;
      if (parser.Has("keep-at-seed") &&
          !step("keep-at-seed",
                SegmentationEditor::KeepComponentAtSeed(segmentation, target.ID, seeds.front(), result, error)))
        return 1;
      if (parser.Has("split") &&
          !step("split", SegmentationEditor::SplitComponents(segmentation, target.ID, split, 1, result, error)))
        return 1;
    }
    const std::string segPath = (outDir / "segmentation.seg.nrrd").string();
    if (!WriteSegmentationFile(segPath, segmentation, error)) {
      err << "roboplan mesh: " << error << "\n";
      return 1;
    }
  }
  return 0;
}

// One closed display + haptic surface per segment, each written on a thread of its own.
void BuildAndWriteModels(const ArgParser& parser, const MeshRequest& request, MeshRun& run,
                         TerminalProgress& progress, std::ostream& err) {
  ModelBuildOptions build = request.Build;
  const std::string& format = request.Format;
  const fs::path& outDir = run.OutDir;
  vtkRPScene* scene = run.Scene;
  vtkRPSegmentationNode* segmentation = run.Segmentation;
  std::vector<SegmentModels>& models = run.Models;
  json& segments = run.Segments;
  int& failures = run.Failures;
  if (parser.Has("grid-mm")) {
    // A grid of about this spacing in mm, never finer than the voxels.
    double spacing[3];
    segmentation->GetSpacing(spacing);
    const double mm = parser.GetDouble("grid-mm");
    for (int a = 0; a < 3; ++a) build.Display.GridStep[a] = std::max(1.0, mm / spacing[a]);
    for (int a = 0; a < 3; ++a) build.Haptic.GridStep[a] = build.Display.GridStep[a];
  }
  progress.Report(0.2, "meshing");
  // Each model's file is written on a thread of its own as soon as the model is built, while
  // the rest meshes (compressing a large mesh takes a good part of the time making it took).
  struct Written {
    bool Ok = true;
    std::string Error;
  };
  auto modelPath = [&](const std::string& segmentID, const std::string& suffix) {
    return (outDir / (SafeFileName(segmentID) + suffix + "." + format)).string();
  };
  std::map<std::string, std::future<Written>> writes;  // by file path
  auto writeSegment = [&](const SegmentModels& m) {
    for (const auto& [model, suffix] : {std::pair{m.DisplayModel, ""}, std::pair{m.HapticModel, "_haptic"}}) {
      const std::string path = model ? modelPath(m.SegmentID, suffix) : std::string();
      if (!model || writes.count(path)) continue;  // not built yet, or already being written
      vtkSmartPointer<vtkPolyData> mesh = model->GetPolyData();
      writes[path] = std::async(std::launch::async, [path, mesh] {
        // A copy of its own: the display mesh is still read while the haptic mesh is made, and
        // writing runs it through a VTK pipeline, which marks its input (update time, ranges).
        auto own = vtkSmartPointer<vtkPolyData>::New();
        own->DeepCopy(mesh);
        Written w;
        w.Ok = WriteModelFile(path, own, w.Error);
        return w;
      });
    }
  };
  models = BuildSegmentModels(
      segmentation, build, scene,
      [&](double f, const std::string& message) { progress.Report(0.2 + 0.75 * f, message); }, writeSegment);
  for (const auto& m : models) {
    json entry = {{"id", m.SegmentID}, {"name", m.Name}, {"tissueClass", m.TissueClass}, {"ok", m.Ok}};
    if (const auto* s = segmentation->GetSegmentByID(m.SegmentID)) entry["labelValue"] = s->LabelValue;
    if (!m.Ok) {
      ++failures;
      entry["error"] = m.Error;
      err << "roboplan mesh: " << m.Error << "\n";
    }
    auto save = [&](vtkRPModelNode* model, const std::string& suffix, const MeshStats& stats, const char* key) {
      if (!model) return;
      const std::string path = modelPath(m.SegmentID, suffix);
      json stat = StatsJson(stats);
      stat["file"] = path;
      const auto write = writes.find(path);
      Written written;
      if (write != writes.end())
        written = write->second.get();
      else  // a segment whose haptic mesh failed: its display mesh is still written
        written.Ok = WriteModelFile(path, model->GetPolyData(), written.Error);
      if (!written.Ok) {
        ++failures;
        stat["error"] = written.Error;
        err << "roboplan mesh: " << written.Error << "\n";
      }
      for (const auto& w : stats.Warnings) err << "roboplan mesh: " << m.SegmentID << suffix << ": " << w << "\n";
      entry[key] = stat;
    };
    save(m.DisplayModel, "", m.Display, "display");
    save(m.HapticModel, "_haptic", m.Haptic, "haptic");
    segments.push_back(entry);
  }
}

// --truth: each segment scored against a truth labelmap (Dice, surface distances).
int ScoreAgainstTruth(const ArgParser& parser, MeshRun& run, bool quiet, std::ostream& err) {
  vtkRPSegmentationNode* segmentation = run.Segmentation;
  std::string& error = run.Error;
  json& truthScores = run.TruthScores;
  {
    vtkNew<vtkRPScalarVolumeNode> truth;
    LabelComparison comparison;
    std::vector<int> labels;
    for (const auto& s : segmentation->GetSegments()) labels.push_back(s.LabelValue);
    if (!ReadVolumeFile(parser.Get("truth"), truth, error) ||
        !CompareLabels(FromNode(segmentation), FromNode(truth), labels, comparison, error)) {
      err << "roboplan mesh: --truth: " << error << "\n";
      return 1;
    }
    truthScores = json::array();
    for (const auto& score : comparison.Scores) {
      const auto* s = segmentation->GetSegmentByLabel(score.Label);
      const std::string name = s ? s->ID : std::to_string(score.Label);
      truthScores.push_back({{"segment", name}, {"truthLabel", score.TruthLabel}, {"dice", score.Dice},
                             {"meanSurfaceDistanceMm", score.MeanSurfaceDistanceMm},
                             {"hausdorff95Mm", score.Hausdorff95Mm}, {"hausdorffMm", score.HausdorffMm}});
      if (!quiet) {
        err << "  " << name << " vs truth label " << score.TruthLabel << ": Dice " << score.Dice;
        if (score.TruthLabel)
          err << ", surface distance mean " << score.MeanSurfaceDistanceMm << " mm, 95 % " << score.Hausdorff95Mm
              << " mm";
        err << "\n";
      }
    }
  }
  return 0;
}

// 3. Report: --json, or a line per segment.
void Report(const ArgParser& parser, const MeshRun& run, double seconds, std::ostream& out, std::ostream& err) {
  const std::string& input = run.Input;
  const fs::path& outDir = run.OutDir;
  const json &inputInfo = run.InputInfo, &segmentationSteps = run.SegmentationSteps, &segments = run.Segments;
  const json &boneSplit = run.BoneSplit, &truthScores = run.TruthScores;
  const std::vector<SegmentModels>& models = run.Models;
  const int failures = run.Failures;
  if (parser.Json()) {
    json doc = {{"input", input}, {"inputKind", inputInfo}, {"out", outDir.string()}, {"ok", failures == 0},
                {"segmentation", segmentationSteps}, {"segments", segments}, {"seconds", seconds}};
    if (!boneSplit.is_null()) doc["boneSplit"] = boneSplit;
    if (!truthScores.is_null()) doc["truth"] = truthScores;
    out << doc.dump(2) << "\n";
  } else {
    for (const auto& m : models) {
      if (!m.Ok) continue;
      err << "  " << m.SegmentID << " (" << (m.TissueClass.empty() ? "no tissue class" : m.TissueClass)
                << "): display " << m.Display.Triangles << " triangles, volume error "
                << m.Display.VolumeErrorPercent << " %, " << (m.Display.Watertight ? "watertight" : "NOT watertight");
      if (m.HapticModel)
        err << "; haptic " << m.Haptic.Triangles << " triangles (" << m.Haptic.Method << ", "
            << (m.Haptic.Manifold ? "closed manifold" : "NOT a closed manifold") << ", max deviation "
            << m.Haptic.MaxDeviationMm << " mm" << (m.Haptic.WithinBudget ? "" : ", OVER BUDGET") << ")";
      err << "\n";
    }
    err << "wrote " << models.size() - static_cast<size_t>(failures) << " segment(s) to " << outDir.string()
              << " in " << seconds << " s\n";
  }
}

}  // namespace

int RunMeshCommand(const std::vector<std::string>& arguments, vtkRPScene* contextScene, std::ostream& out,
                   std::ostream& err) {
  ArgParser parser(
      "mesh",
      "Segment a volume (threshold presets, region growing, confidence connected, morphology, components) or "
      "take a segmentation (.seg.nrrd), and write one closed surface per segment (display + haptic mesh) to --out.");
  DeclareOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  const auto t0 = std::chrono::steady_clock::now();
  const bool quiet = parser.Json();
  TerminalProgress progress("mesh", quiet, err);
  MeshRequest request;
  if (!ParseRequest(parser, request, err)) return 2;

  MeshRun run;
  run.Input = parser.Get("input");
  run.OutDir = parser.Get("out");
  std::error_code ec;
  fs::create_directories(run.OutDir, ec);
  if (ec) {
    err << "roboplan mesh: cannot create output folder '" << run.OutDir.string() << "': " << ec.message() << "\n";
    return 1;
  }
  vtkNew<vtkRPScene> ownScene;
  run.Scene = contextScene ? contextScene : ownScene.GetPointer();
  if (const int exitCode = LoadInput(parser, run, progress, err)) return exitCode;
  if (run.Segmentation && parser.Has("labels"))
    err << "roboplan mesh: --labels ignored: '" << run.Input << "' is a segmentation with its own segment names\n";
  if (!run.Segmentation)
    if (const int exitCode = SegmentationFromLabelmap(parser, request, run, quiet, err)) return exitCode;
  if (!run.Segmentation && parser.Has("split-bones"))
    if (const int exitCode = SplitBonesIntoSegments(parser, request, run, progress, quiet, err)) return exitCode;
  if (!run.Segmentation)
    if (const int exitCode = SegmentByThreshold(parser, request, run, progress, err)) return exitCode;
  BuildAndWriteModels(parser, request, run, progress, err);
  if (parser.Has("truth"))
    if (const int exitCode = ScoreAgainstTruth(parser, run, quiet, err)) return exitCode;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress.Report(1.0, "done");
  Report(parser, run, seconds, out, err);
  return run.Failures == 0 && !run.Models.empty() ? 0 : 1;
}

}  // namespace rp
