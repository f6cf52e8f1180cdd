// `roboplan mesh` in three parts: parse the options (rpMeshRequest.cxx) → run the module's logic
// (vtkRPSegmentationToMeshLogic, the functions the panel and the demo call) → report.
#include "rpMeshCommand.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <future>
#include <map>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "rpMeshRequest.h"
#include "rpModelIO.h"
#include "rpSegmentationIO.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSegmentationToMeshLogic.h"

namespace rp {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

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

std::string SafeFileName(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return name.empty() ? "segment" : name;
}

// 2. Run: the logic, the scene's nodes and what each step made, for the report. Each step
// returns 0 to go on, else the command's exit code (the problem named on `err`).
struct MeshRun {
  const MeshRequest& Request;
  vtkRPSegmentationToMeshLogic* Logic;
  TerminalProgress& Progress;
  std::ostream& Err;
  vtkRPNode* Loaded = nullptr;
  vtkRPSegmentationNode* Segmentation = nullptr;
  json SegmentationSteps = json::array();
  json InputInfo = {{"kind", "segmentation"}, {"reason", "a segmentation file"}};
  json BoneSplit = nullptr, TruthScores = nullptr, Segments = json::array();
  std::vector<SegmentModels> Models = {};
  int Failures = 0;

  int Fail(int exitCode, const std::string& message) {
    this->Err << "roboplan mesh: " << message << "\n";
    return exitCode;
  }
  // The segmentation a volume became, written beside the models.
  int WriteSegmentation() {
    std::string error;
    if (!WriteSegmentationFile((this->Request.OutDir / "segmentation.seg.nrrd").string(), this->Segmentation, error))
      return this->Fail(1, error);
    return 0;
  }
};

// The input, through the one loader (a volume or a segmentation).
int LoadInput(MeshRun& run) {
  run.Progress.Report(0.0, "loading " + run.Request.Input);
  std::vector<std::string> warnings;
  std::string error;
  run.Loaded = run.Logic->LoadInput(run.Request.Input, run.Request.Read, warnings, error);
  for (const auto& warning : warnings) run.Err << "roboplan mesh: warning: " << warning << "\n";
  if (!run.Loaded) return run.Fail(1, error);
  run.Segmentation = vtkRPSegmentationNode::SafeDownCast(run.Loaded);
  return 0;
}

// A volume that is a labelmap becomes a segmentation (one segment per label value).
int SegmentationFromLabelmap(MeshRun& run) {
  const MeshRequest& request = run.Request;
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(run.Loaded);
  if (!volume) return run.Fail(1, "'" + request.Input + "' is neither a volume nor a segmentation");
  const InputChoice choice = ChooseInputKind(request.Kind, volume->GetImageData(), request.Input,
                                             !request.Labels.empty(), request.IntensityOptions);
  run.InputInfo = {{"kind", choice.Labelmap ? "labelmap" : "intensity"}, {"reason", choice.Reason}};
  // The labelmap hint goes to the error stream even with --json (a run that then finds empty
  // segments would otherwise say only that).
  const bool hint = choice.Reason.find("--input-kind labelmap") != std::string::npos && !choice.Labelmap;
  if (!request.Json || hint) run.Err << "input: " << choice.Reason << "\n";
  std::string error;
  if (choice.Labelmap) {
    LabelTable table;
    if (!request.Labels.empty() && !ReadLabelTable(request.Labels, table, error)) return run.Fail(1, error);
    // The volume is not used again: the segmentation takes its voxels as they are.
    run.Segmentation = run.Logic->SegmentationFromLabelmap(volume, request.Labels.empty() ? nullptr : &table,
                                                           volume->GetName() + " segmentation", false, error,
                                                           choice.Scanned ? &choice.Values : nullptr);
    if (!run.Segmentation) return run.Fail(1, "'" + request.Input + "': " + error);
  } else if (!request.Labels.empty()) {
    return run.Fail(2, "--labels names the values of a labelmap, but '" + request.Input +
                           "' is taken as an intensity image (" + choice.Reason + ")");
  }
  return 0;
}

// --split-bones: the bones of a CT one by one.
int SplitBonesIntoSegments(MeshRun& run) {
  const MeshRequest& request = run.Request;
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(run.Loaded);
  BoneSplitOptions options = request.Bones;
  std::string error;
  for (const auto& text : request.BoneSeeds) {
    BoneSeed seed;
    if (!ParseBoneSeed(text, seed, error)) return run.Fail(2, "--bone-seed " + error);
    options.Seeds.push_back(seed);
  }
  for (const auto& p : request.Method.Seeds) options.Seeds.push_back({p, ""});
  BoneSplitResult split;
  run.Segmentation = run.Logic->SplitBones(volume, options, volume->GetName() + " bones", split, error,
                                           [&](double f, const std::string& m) {
                                             run.Progress.Report(0.05 + 0.15 * f, "bones: " + m);
                                           });
  if (!run.Segmentation) return run.Fail(1, "--split-bones: " + error);
  json bones = json::array();
  for (const auto& b : split.Bones)
    bones.push_back({{"id", b.ID}, {"labelValue", b.LabelValue}, {"volumeMl", b.VolumeMl}, {"namedBy", b.NamedBy},
                     {"centroidRAS", {b.CentroidRAS[0], b.CentroidRAS[1], b.CentroidRAS[2]}}});
  run.BoneSplit = {{"bones", bones}, {"splits", split.Splits}, {"droppedSpecks", split.DroppedSpecks},
                   {"droppedSpecksMl", split.DroppedSpecksMl}, {"droppedOutsideBody", split.DroppedOutsideBody},
                   {"droppedOutsideBodyMl", split.DroppedOutsideBodyMl}, {"notes", split.Notes},
                   {"seconds", split.Seconds}};
  if (!request.Json) {
    run.Err << "bones: " << split.Bones.size() << " (" << split.Splits << " touching pair(s) split; dropped "
            << split.DroppedSpecks << " speck(s) and " << split.DroppedOutsideBody
            << " piece(s) outside the body outline)\n";
    for (const auto& b : split.Bones)
      run.Err << "  " << b.ID << ": " << b.VolumeMl << " ml" << (b.NamedBy.empty() ? "" : ", named by " + b.NamedBy)
              << "\n";
    for (const auto& n : split.Notes) run.Err << "  note: " << n << "\n";
  }
  return run.WriteSegmentation();
}

// An intensity volume: one segment per tissue (presets or one range), each with its edits.
int SegmentTissues(MeshRun& run) {
  const MeshRequest& request = run.Request;
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(run.Loaded);
  std::vector<ThresholdPreset> tissues;
  for (const auto& name : request.Presets) tissues.push_back(*FindThresholdPreset(name));  // names: OneOf
  if (request.Lower || request.Upper) {
    if (tissues.size() != 1) return run.Fail(2, "--lower/--upper apply to one tissue; give at most one --preset");
    if (request.Lower) tissues[0].Lower = *request.Lower;
    if (request.Upper) tissues[0].Upper = *request.Upper;
  }
  run.Segmentation = run.Logic->AddSegmentation(volume->GetName() + " segmentation");
  for (size_t t = 0; t < tissues.size(); ++t) {
    const auto& tissue = tissues[t];
    TissueRecipe recipe;
    recipe.Target = {tissue.Name, tissue.Name, tissue.TissueClass, tissue.Color, false, request.MaxFraction};
    recipe.Method = request.Method;
    recipe.Method.Lower = tissue.Lower;
    recipe.Method.Upper = tissue.Upper;
    recipe.Edits = request.Edits;
    run.Progress.Report(0.05 + 0.1 * t / tissues.size(), "segmenting " + tissue.Name);
    std::vector<TissueStep> steps;
    std::string error;
    const bool ok = run.Logic->SegmentTissue(volume, run.Segmentation, recipe, steps, error);
    for (const TissueStep& step : steps)
      run.SegmentationSteps.push_back({{"segment", step.Segment}, {"step", step.Step}, {"ok", step.Ok},
                                       {"voxels", step.Result.Voxels}, {"fraction", step.Result.Fraction},
                                       {"components", step.Result.Components}});
    if (!ok) return run.Fail(1, steps.back().Segment + " " + steps.back().Step + ": " + error);
  }
  return run.WriteSegmentation();
}

// One closed display + haptic surface per segment, each written on a thread of its own as soon
// as it is built, while the rest meshes (compressing a large mesh takes a good part of the time
// making it took).
void BuildAndWriteModels(MeshRun& run) {
  const MeshRequest& request = run.Request;
  ModelBuildOptions build = request.Build;
  if (request.GridMm) {
    // A grid of about this spacing in mm, never finer than the voxels.
    double spacing[3];
    run.Segmentation->GetSpacing(spacing);
    for (int a = 0; a < 3; ++a) build.Display.GridStep[a] = std::max(1.0, *request.GridMm / spacing[a]);
    for (int a = 0; a < 3; ++a) build.Haptic.GridStep[a] = build.Display.GridStep[a];
  }
  run.Progress.Report(0.2, "meshing");
  struct Written {
    bool Ok = true;
    std::string Error;
  };
  auto modelPath = [&](const std::string& segmentID, const std::string& suffix) {
    return (request.OutDir / (SafeFileName(segmentID) + suffix + "." + request.Format)).string();
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
  run.Models = run.Logic->CreateModels(
      run.Segmentation, build, [&](double f, const std::string& message) { run.Progress.Report(0.2 + 0.75 * f, message); },
      writeSegment);
  for (const auto& m : run.Models) {
    json entry = {{"id", m.SegmentID}, {"name", m.Name}, {"tissueClass", m.TissueClass}, {"ok", m.Ok}};
    if (const auto* s = run.Segmentation->GetSegmentByID(m.SegmentID)) entry["labelValue"] = s->LabelValue;
    if (!m.Ok) {
      ++run.Failures;
      entry["error"] = m.Error;
      run.Err << "roboplan mesh: " << m.Error << "\n";
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
        ++run.Failures;
        stat["error"] = written.Error;
        run.Err << "roboplan mesh: " << written.Error << "\n";
      }
      for (const auto& w : stats.Warnings) run.Err << "roboplan mesh: " << m.SegmentID << suffix << ": " << w << "\n";
      entry[key] = stat;
    };
    save(m.DisplayModel, "", m.Display, "display");
    save(m.HapticModel, "_haptic", m.Haptic, "haptic");
    run.Segments.push_back(entry);
  }
}

// --truth: each segment scored against a truth labelmap (Dice, surface distances).
int ScoreAgainstTruth(MeshRun& run) {
  LabelComparison comparison;
  std::string error;
  if (!run.Logic->CompareWithTruth(run.Segmentation, run.Request.Truth, comparison, error))
    return run.Fail(1, "--truth: " + error);
  run.TruthScores = json::array();
  for (const auto& score : comparison.Scores) {
    const auto* s = run.Segmentation->GetSegmentByLabel(score.Label);
    const std::string name = s ? s->ID : std::to_string(score.Label);
    run.TruthScores.push_back({{"segment", name}, {"truthLabel", score.TruthLabel}, {"dice", score.Dice},
                               {"meanSurfaceDistanceMm", score.MeanSurfaceDistanceMm},
                               {"hausdorff95Mm", score.Hausdorff95Mm}, {"hausdorffMm", score.HausdorffMm}});
    if (run.Request.Json) continue;
    run.Err << "  " << name << " vs truth label " << score.TruthLabel << ": Dice " << score.Dice;
    if (score.TruthLabel)
      run.Err << ", surface distance mean " << score.MeanSurfaceDistanceMm << " mm, 95 % " << score.Hausdorff95Mm
              << " mm";
    run.Err << "\n";
  }
  return 0;
}

// 3. Report: --json, or a line per segment.
void Report(const MeshRun& run, double seconds, std::ostream& out) {
  const MeshRequest& request = run.Request;
  if (request.Json) {
    json doc = {{"input", request.Input},      {"inputKind", run.InputInfo},
                {"out", request.OutDir.string()}, {"ok", run.Failures == 0},
                {"segmentation", run.SegmentationSteps}, {"segments", run.Segments},
                {"seconds", seconds}};
    if (!run.BoneSplit.is_null()) doc["boneSplit"] = run.BoneSplit;
    if (!run.TruthScores.is_null()) doc["truth"] = run.TruthScores;
    out << doc.dump(2) << "\n";
    return;
  }
  for (const auto& m : run.Models) {
    if (!m.Ok) continue;
    run.Err << "  " << m.SegmentID << " (" << (m.TissueClass.empty() ? "no tissue class" : m.TissueClass)
            << "): display " << m.Display.Triangles << " triangles, volume error " << m.Display.VolumeErrorPercent
            << " %, " << (m.Display.Watertight ? "watertight" : "NOT watertight");
    if (m.HapticModel)
      run.Err << "; haptic " << m.Haptic.Triangles << " triangles (" << m.Haptic.Method << ", "
              << (m.Haptic.Manifold ? "closed manifold" : "NOT a closed manifold") << ", max deviation "
              << m.Haptic.MaxDeviationMm << " mm" << (m.Haptic.WithinBudget ? "" : ", OVER BUDGET") << ")";
    run.Err << "\n";
  }
  run.Err << "wrote " << run.Models.size() - static_cast<size_t>(run.Failures) << " segment(s) to "
          << request.OutDir.string() << " in " << seconds << " s\n";
}

int Run(MeshRun& run) {
  const MeshRequest& request = run.Request;
  if (const int exitCode = LoadInput(run)) return exitCode;
  if (run.Segmentation && !request.Labels.empty())
    run.Err << "roboplan mesh: --labels ignored: '" << request.Input
            << "' is a segmentation with its own segment names\n";
  if (!run.Segmentation)
    if (const int exitCode = SegmentationFromLabelmap(run)) return exitCode;
  if (!run.Segmentation && request.SplitBones)
    if (const int exitCode = SplitBonesIntoSegments(run)) return exitCode;
  if (!run.Segmentation)
    if (const int exitCode = SegmentTissues(run)) return exitCode;
  BuildAndWriteModels(run);
  if (!request.Truth.empty())
    if (const int exitCode = ScoreAgainstTruth(run)) return exitCode;
  return 0;
}

}  // namespace

int RunMeshCommand(const std::vector<std::string>& arguments, vtkRPScene* contextScene, std::ostream& out,
                   std::ostream& err) {
  ArgParser parser(
      "mesh",
      "Segment a volume (threshold presets, region growing, confidence connected, morphology, components) or "
      "take a segmentation (.seg.nrrd), and write one closed surface per segment (display + haptic mesh) to --out.");
  DeclareMeshOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  const auto t0 = std::chrono::steady_clock::now();
  MeshRequest request;
  if (!ParseMeshRequest(parser, request, err)) return 2;
  TerminalProgress progress("mesh", request.Json, err);
  std::error_code ec;
  fs::create_directories(request.OutDir, ec);
  if (ec) {
    err << "roboplan mesh: cannot create output folder '" << request.OutDir.string() << "': " << ec.message() << "\n";
    return 1;
  }
  vtkNew<vtkRPScene> ownScene;
  vtkNew<vtkRPSegmentationToMeshLogic> logic;
  logic->SetScene(contextScene ? contextScene : ownScene.GetPointer());
  MeshRun run{request, logic, progress, err};
  if (const int exitCode = Run(run)) return exitCode;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress.Report(1.0, "done");
  Report(run, seconds, out);
  return run.Failures == 0 && !run.Models.empty() ? 0 : 1;
}

}  // namespace rp
