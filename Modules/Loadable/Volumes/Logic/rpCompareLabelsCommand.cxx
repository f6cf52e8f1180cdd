// `roboplan compare-labels <segmentation> <truth labelmap>`: Dice and surface distances per segment,
// read and scored by the Volumes logic (LoadLabelmap, CompareLabels); the command parses and reports.
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpNodeStorage.h"
#include "rpProgress.h"
#include "rpVolumesCommands.h"
#include "vtkRPScene.h"
#include "vtkRPVolumesLogic.h"
#include "rpStrings.h"

namespace rp {
namespace {

nlohmann::json Distance(double mm) { return mm < 0 ? nlohmann::json() : nlohmann::json(mm); }

}  // namespace

int RunCompareLabelsCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("compare-labels",
                   "Score a segmentation against a truth labelmap, segment by segment: Dice, and the symmetric "
                   "surface distance between the two boundaries (mean, 95th percentile, maximum; mm). Each segment "
                   "is matched to the truth label it overlaps most, so label numbers need not agree. The truth is "
                   "sampled onto the segmentation's grid (nearest voxel) when the grids differ.");
  auto labelFiles = ExtensionsForNodeClass("vtkRPSegmentationNode");
  for (const auto& ext : ExtensionsForNodeClass("vtkRPScalarVolumeNode")) labelFiles.push_back(ext);
  parser.Positional("segmentation", "segmentation (.seg.nrrd) or labelmap volume to score")
      .Input(FileKind::LabelMap, labelFiles)
      .Positional("truth", "truth labelmap (or segmentation)")
      .Input(FileKind::LabelMap, labelFiles)
      .Option("label", "n", "score only this label value of <segmentation> (repeatable; default: all)")
      .Integer()
      .AtLeast(1)
      .Repeatable();
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  TerminalProgress progress("compare-labels", parser.Json(), err);
  // Read and scored by the Volumes logic, in a scene of the command's own.
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  std::string error;
  progress.Report(0.0, "loading");
  vtkRPNode* segmentation = logic->LoadLabelmap(parser.Get("segmentation"), error);
  vtkRPNode* truth = segmentation ? logic->LoadLabelmap(parser.Get("truth"), error) : nullptr;
  if (!truth) {
    err << "roboplan compare-labels: " << error << "\n";
    return 1;
  }
  std::vector<int> labels;
  for (const auto& text : parser.GetAll("label")) labels.push_back(std::stoi(text));
  progress.Report(0.2, "scoring");
  vtkRPVolumesLogic::LabelScores scores;
  if (!logic->CompareLabels(segmentation, truth, labels, scores, error)) {
    err << "roboplan compare-labels: " << error << "\n";
    return 1;
  }
  const LabelComparison& comparison = scores.Comparison;
  auto& names = scores.Names;
  auto& truthNames = scores.TruthNames;
  using LabelName = vtkRPVolumesLogic::LabelName;
  progress.Report(1.0, "done");
  if (parser.Json()) {
    nlohmann::json segments = nlohmann::json::array();
    for (const auto& s : comparison.Scores) {
      const auto name = names.count(s.Label) ? names[s.Label] : LabelName{std::to_string(s.Label), "label " + std::to_string(s.Label)};
      segments.push_back({{"segment", name.ID}, {"name", name.Name}, {"labelValue", s.Label},
                          {"truthLabel", s.TruthLabel ? nlohmann::json(s.TruthLabel) : nlohmann::json()},
                          {"truthName", truthNames.count(s.TruthLabel) ? truthNames[s.TruthLabel].Name : ""},
                          {"voxels", s.Voxels}, {"truthVoxels", s.TruthVoxels}, {"overlapVoxels", s.OverlapVoxels},
                          {"dice", s.Dice}, {"meanSurfaceDistanceMm", Distance(s.MeanSurfaceDistanceMm)},
                          {"hausdorff95Mm", Distance(s.Hausdorff95Mm)}, {"hausdorffMm", Distance(s.HausdorffMm)}});
    }
    out << nlohmann::json{{"ok", true}, {"segmentation", parser.Get("segmentation")}, {"truth", parser.Get("truth")},
                          {"truthResampled", comparison.TruthResampled}, {"segments", segments},
                          {"unmatchedTruthLabels", comparison.UnmatchedTruth}}
               .dump(2)
        << "\n";
    return 0;
  }
  for (const auto& s : comparison.Scores) {
    out << "label " << s.Label;
    if (names.count(s.Label)) out << " (" << names[s.Label].Name << ")";
    if (!s.TruthLabel) {
      out << ": overlaps no truth label\n";
      continue;
    }
    out << " vs truth " << s.TruthLabel << ": Dice " << Fixed(s.Dice, 3) << ", surface distance mean "
        << Fixed(s.MeanSurfaceDistanceMm, 3) << " mm, 95% " << Fixed(s.Hausdorff95Mm, 3) << " mm, max "
        << Fixed(s.HausdorffMm, 3) << " mm\n";
  }
  for (int t : comparison.UnmatchedTruth) out << "truth label " << t << ": no segment matched it\n";
  return 0;
}

}  // namespace rp
