#include "rpDemoStages.h"

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpDicomEntries.h"
#include "rpDicomSeries.h"
#include "rpDicomWriter.h"
#include "rpImageVolume.h"
#include "rpBoneScores.h"
#include "rpBoneSplit.h"
#include "rpKneeBoneNames.h"
#include "rpKneePhantom.h"
#include "rpLabelTable.h"
#include "rpVolumeFiles.h"
#include "rpReport.h"
#include "vtkRPSegmentationToMeshLogic.h"
#include "rpSurfaceError.h"
#include "vtkRPModelNode.h"
#include "vtkRPSegmentationNode.h"
#include "rpVolumeIO.h"
#include "rpVolumeRegistration.h"
#include "vtkRPLinearTransformNode.h"
#include "rpStageRunner.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPVolumesLogic.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

ProgressCallback StageProgress(DemoState& state) {
  return [&state](double f, const std::string& m) { state.Runner->Progress(f, m); };
}

// ---- Stage: the knee phantom (or nothing, with --data)
void GeneratePhantom(DemoState& state) {
  if (!state.Options.DicomData.empty()) return;  // a user's data: no phantom, no ground truth
  KneePhantomOptions options;
  if (state.Options.PhantomSize == "small") {
    options.Size = KneePhantomSize::Small;
  } else if (state.Options.PhantomSize == "full") {
    options.Size = KneePhantomSize::Full;
  } else if (state.Options.PhantomSize == "demo") {
    options.Size = KneePhantomSize::Demo;
  } else {
    throw std::runtime_error("unknown phantom size '" + state.Options.PhantomSize + "' (small, demo, full)");
  }
  auto phantom = std::make_shared<KneePhantom>();
  std::string error;
  if (!GenerateKneePhantom(options, *phantom, error, StageProgress(state))) {
    throw std::runtime_error("knee phantom: " + error);
  }
  state.Phantom = phantom;
  phantom->Model->KneeAxes(state.KneeLateral.data(), state.KneeAnterior.data());
  state.KneeAxesKnown = true;
  // The ground-truth labelmap is kept beside the scene for scoring (not a scene node).
  if (!WriteVolumeFile((fs::path(state.Output) / "ground-truth-labels.nrrd").string(), phantom->Labels.Image,
                       phantom->Labels.IJKToRAS, {}, error)) {
    throw std::runtime_error(error);
  }
  int dims[3];
  phantom->CT.Image->GetDimensions(dims);
  double spacing[3];
  phantom->CT.GetSpacing(spacing);
  state.Report->AddFigure("Knee phantom", "CT voxels", double(dims[0]) * dims[1] * dims[2], "",
                          std::to_string(dims[0]) + "×" + std::to_string(dims[1]) + "×" + std::to_string(dims[2]) +
                              " at " + std::to_string(spacing[0]).substr(0, 4) + "×" +
                              std::to_string(spacing[1]).substr(0, 4) + "×" + std::to_string(spacing[2]).substr(0, 4) +
                              " mm");
}

// ---- Stage: the CT and MR written as DICOM series by our writer and read back by our reader
vtkRPScalarVolumeNode* AddVolumeNode(DemoState& state, const ImageVolume& volume, const std::string& name) {
  vtkNew<vtkRPScalarVolumeNode> node;
  node->SetName(name);
  CopyToNode(volume, node.GetPointer());
  if (volume.Window <= 0) node->SetWindowLevelFromScalarRange();
  state.Scene->AddNode(node);
  return node;
}

double MaxVoxelDifference(vtkImageData* a, vtkImageData* b) {
  int da[3], db[3];
  a->GetDimensions(da);
  b->GetDimensions(db);
  if (da[0] != db[0] || da[1] != db[1] || da[2] != db[2]) return std::numeric_limits<double>::infinity();
  double worst = 0;
  const vtkIdType n = a->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i) {
    worst = std::max(worst, std::abs(a->GetPointData()->GetScalars()->GetTuple1(i) -
                                     b->GetPointData()->GetScalars()->GetTuple1(i)));
  }
  return worst;
}

double MaxMatrixDifference(const vtkMatrix4x4* a, const vtkMatrix4x4* b) {
  double worst = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) worst = std::max(worst, std::abs(a->GetElement(i, j) - b->GetElement(i, j)));
  return worst;
}

void DicomRoundTrip(DemoState& state) {
  const std::string stage = "DICOM series";
  std::string error;
  if (!state.HasGroundTruth()) {
    vtkNew<vtkRPVolumesLogic> volumes;
    volumes->SetScene(state.Scene);
    DicomScanResult scan;
    if (!volumes->ScanDicomFolder(state.Options.DicomData, scan, error, StageProgress(state)))
      throw std::runtime_error(error);
    const DicomSeriesInfo* chosen = nullptr;
    for (const auto& series : scan.Series) {
      if (series.Problem.empty() && (!chosen || series.Files.size() > chosen->Files.size())) chosen = &series;
    }
    if (!chosen) throw std::runtime_error("no loadable image series in '" + state.Options.DicomData + "'");
    // Read through the Volumes logic (the loader's DICOM reader), as register-volumes and the
    // viewer's loader read a series.
    VolumeReadOptions read;
    read.SeriesInstanceUID = chosen->StackID;
    std::vector<std::string> warnings;
    state.CT = volumes->LoadVolume(state.Options.DicomData, "CT", error, read, StageProgress(state), &warnings);
    if (!state.CT) throw std::runtime_error(error);
    for (const auto& w : warnings) state.Report->AddNote("DICOM: " + w);
    state.Report->AddFigure(stage, "slices read", double(chosen->Files.size()), "",
                            chosen->Modality + " " + chosen->SeriesDescription);
    return;
  }
  DicomWriteOptions options;
  options.Modality = "CT";
  options.SeriesDescription = "RoboPlan knee phantom CT";
  DicomWriteResult written;
  const std::string ctFolder = (fs::path(state.Output) / "dicom" / "CT").string();
  const std::string mrFolder = (fs::path(state.Output) / "dicom" / "MR").string();
  // The writer with its result (the study's UID), loaded here with DCMTK (rpDicomEntries.h).
  const auto writeSeries = dicom::Entry<dicom::WriteSeriesFunction>(dicom::WriteSeriesEntry, ctFolder, error);
  if (!writeSeries) throw std::runtime_error("writing the CT series: " + error);
  if (!writeSeries(state.Phantom->CT, ctFolder, options, error, &written, StageProgress(state))) {
    throw std::runtime_error("writing the CT series: " + error);
  }
  options.Modality = "MR";
  options.SeriesDescription = "RoboPlan knee phantom PD MR";
  options.SeriesNumber = 2;
  options.StudyInstanceUID = written.StudyInstanceUID;  // one study, two series
  if (!writeSeries(state.Phantom->MR, mrFolder, options, error, nullptr, StageProgress(state))) {
    throw std::runtime_error("writing the MR series: " + error);
  }
  ImageVolume ct, mr;
  if (!ReadVolume(ctFolder, ct, error)) throw std::runtime_error("reading the CT series back: " + error);
  if (!ReadVolume(mrFolder, mr, error)) throw std::runtime_error("reading the MR series back: " + error);
  const double ctVoxels = MaxVoxelDifference(ct.Image, state.Phantom->CT.Image);
  const double mrVoxels = MaxVoxelDifference(mr.Image, state.Phantom->MR.Image);
  state.Report->AddFigureBelow(stage, "CT voxels changed by the DICOM round trip (max |Δ|)", ctVoxels, "HU", 0.5);
  state.Report->AddFigureBelow(stage, "MR voxels changed by the DICOM round trip (max |Δ|)", mrVoxels, "", 0.5);
  state.Report->AddFigureBelow(stage, "CT IJK-to-RAS change (max |Δ| element)",
                               MaxMatrixDifference(ct.IJKToRAS, state.Phantom->CT.IJKToRAS), "mm", 1e-3);
  state.Report->AddFigureBelow(stage, "MR IJK-to-RAS change (max |Δ| element)",
                               MaxMatrixDifference(mr.IJKToRAS, state.Phantom->MR.IJKToRAS), "mm", 1e-3);
  state.CT = AddVolumeNode(state, ct, "CT");
  state.MR = AddVolumeNode(state, mr, "MR");
}

// ---- Stage: CT↔MR rigid registration by Mattes mutual information
void RegisterCTAndMR(DemoState& state) {
  const std::string stage = "CT↔MR registration";
  if (!state.MR) {
    state.Report->AddNotScored(stage, "CT↔MR registration", "no MR series (a user's CT only)");
    return;
  }
  RigidRegistrationOptions options;
  options.InitialFixedToMoving = vtkSmartPointer<vtkMatrix4x4>::New();  // scanner coordinates as the start
  // Speed over the last tenth of a millimetre: two levels, the finest at about 1.6 mm voxels
  // whatever the grid (the demo's 0.8 mm CT: every second voxel; the small phantom's 1.6 mm CT:
  // every voxel, where skipping it left 3.2 mm voxels and 1.35 mm RMS at the bone), and fewer
  // voxels sampled.
  double spacing[3];
  state.CT->GetSpacing(spacing);
  const unsigned finest = std::max(1u, static_cast<unsigned>(std::lround(1.6 / std::min({spacing[0], spacing[1], spacing[2]}))));
  options.ShrinkFactors = {2 * finest, finest};
  options.SmoothingSigmasMM = {2.0, 1.0};
  options.SamplingFraction = 0.1;
  options.MaxIterationsPerLevel = 100;
  RigidRegistrationResult result;
  std::string error;
  // The Volumes logic, as a host's: MR under MRToCT (its "to parent" matrix is moving → fixed).
  vtkNew<vtkRPVolumesLogic> volumes;
  volumes->SetScene(state.Scene);
  if (!volumes->RegisterVolumes(state.CT, state.MR, options, result, error, StageProgress(state)))
    throw std::runtime_error(error);
  state.Report->AddFigure(stage, "registration time", result.Seconds, "s", std::to_string(result.Iterations) + " iterations");
  if (state.HasGroundTruth()) {
    std::vector<std::array<double, 3>> bone;
    for (KneeStructure s : {KneeStructure::Femur, KneeStructure::Tibia, KneeStructure::Patella}) {
      const auto points = state.Phantom->Model->SurfacePoints(s, 2000);
      bone.insert(bone.end(), points.begin(), points.end());
    }
    const double rms = TransformRMSDifference(result.FixedToMoving, state.Phantom->CTToMR, bone);
    state.Report->AddFigureBelow(stage, "RMS error at the bone surface (vs the true CT→MR pose)", rms, "mm", 1.0);
  }
}

// ---- Stage: bones and soft tissues segmented on the CT and meshed (display + haptic LoD)

// Each bone in its own colour: a knee bone's (by segment ID or name, rp::BoneColor: the one bone
// colour table), else a distinct one.
void ColourBones(vtkRPSegmentationNode* segmentation, const std::vector<std::string>& boneIDs) {
  long other = 0;
  for (const std::string& id : boneIDs) {
    const vtkRPSegmentationNode::Segment* found = segmentation->GetSegmentByID(id);
    if (!found) continue;
    vtkRPSegmentationNode::Segment segment = *found;
    std::array<double, 3> colour;
    if (!KneeBoneColor(id, colour) && !KneeBoneColor(segment.Name, colour)) colour = DefaultLabelColor(++other);
    for (int c = 0; c < 3; ++c) segment.Color[c] = colour[c];
    segmentation->SetSegment(segment);
  }
}

// Per bone: Dice and surface distances against the phantom's truth or the user's --truth labels.
void ScoreSegmentedBones(DemoState& state, const std::vector<SegmentModels>& built, const double bounds[6],
                         const std::string& stage) {
  std::string error;
  std::vector<TruthBone> truth;
  std::string against;
  if (state.HasGroundTruth()) {
    truth = PhantomTruthBones(state.Phantom->Labels, *state.Phantom->Model, state.Segmentation, error);
    against = "the true surface";
  } else if (!state.Options.TruthLabels.empty()) {
    ImageVolume labels;
    if (!ReadVolume(state.Options.TruthLabels, labels, error)) throw std::runtime_error("--truth: " + error);
    std::vector<std::string> names;
    if (!state.Options.TruthNames.empty()) {
      LabelTable table;
      if (!ReadLabelTable(state.Options.TruthNames, table, error)) throw std::runtime_error("--truth-names: " + error);
      for (const LabelEntry& entry : table.Entries) {
        if (entry.Value < 0 || entry.Value > 65535) continue;
        if (names.size() <= size_t(entry.Value)) names.resize(size_t(entry.Value) + 1);
        names[size_t(entry.Value)] = entry.Name;
      }
    }
    truth = LabelmapTruthBones(labels, names, state.Segmentation, error);
    against = "the truth label's surface";
  } else {
    state.Report->AddNotScored(stage, "Dice and surface distance per bone",
                               "no ground truth for a user's CT (give one with --truth labels.nrrd)");
    return;
  }
  if (truth.empty()) throw std::runtime_error("scoring: " + error);
  double spacing[3];
  state.CT->GetSpacing(spacing);
  const double voxel = std::min({spacing[0], spacing[1], spacing[2]});
  auto meshOf = [&](const std::string& segmentID) -> vtkPolyData* {
    for (const SegmentModels& m : built)
      if (m.SegmentID == segmentID && m.DisplayModel) return m.DisplayModel->GetPolyData();
    return nullptr;
  };
  // The targets for bones from a real CT: Dice >= 0.90, mean distance <= 0.8 mm.
  for (const BoneScore& score : ScoreBones(truth, state.Segmentation, meshOf, bounds)) {
    if (score.SegmentID.empty()) {
      state.Report->AddFigureAbove(stage, score.Truth + ": Dice", 0.0, "", 0.9, "no segment overlaps this bone");
      continue;
    }
    const std::string matched = "segment " + score.SegmentName;
    state.Report->AddFigureAbove(stage, score.Truth + ": Dice", score.Dice, "", 0.9, matched);
    if (!score.HasSurface) continue;
    state.Report->AddFigureBelow(stage, score.Truth + ": mean surface distance to " + against, score.Surface.MeanMm,
                                 "mm", 0.8,
                                 matched + "; " + std::to_string(score.Surface.MeanMm / voxel).substr(0, 4) +
                                     " voxel; inside the CT less 3 mm");
    state.Report->AddFigure(stage, score.Truth + ": 95 % surface distance", score.Surface.Percentile95Mm, "mm",
                            "both directions pooled; Hausdorff " + std::to_string(score.Surface.HausdorffMm).substr(0, 5) +
                                " mm");
  }
}

void SegmentAndMesh(DemoState& state) {
  const std::string stage = "Segmentation and meshing";
  std::string error;
  vtkNew<vtkRPSegmentationToMeshLogic> logic;  // as the SegmentationToMesh panel and `roboplan mesh`
  logic->SetScene(state.Scene);
  // Bones one by one, the same way for the phantom and a user's CT: threshold and fill, pieces
  // outside the body dropped, touching bones split at narrow contacts, knee bones named from
  // their position and size (no seeds: the phantom gets no help a real case would not get).
  BoneSplitResult split;
  vtkRPSegmentationNode* segmentation =
      logic->SplitBones(state.CT, BoneSplitOptions(), "KneeSegmentation", split, error,
                        [&state](double f, const std::string& m) { state.Runner->Progress(0.25 * f, "bones: " + m); });
  if (!segmentation) throw std::runtime_error("bones one by one: " + error);
  std::vector<std::string> boneIDs;
  for (const BoneInfo& b : split.Bones) boneIDs.push_back(b.ID);
  state.Report->AddFigure(stage, "bones found", double(split.Bones.size()), "",
                          std::to_string(split.Splits) + " touching pair(s) split in " +
                              std::to_string(split.Seconds).substr(0, 4) + " s; dropped " +
                              std::to_string(split.DroppedSpecks) + " speck(s), " +
                              std::to_string(split.DroppedOutsideBody) + " piece(s) outside the body");
  for (const std::string& note : split.Notes) state.Report->AddNote("Bones one by one: " + note);
  ColourBones(segmentation, boneIDs);
  if (boneIDs.empty()) throw std::runtime_error("no bone could be segmented");
  state.Runner->Progress(0.3, "soft tissue and fat");
  // Soft tissue and fat: each its preset's threshold, then its largest component.
  for (const auto& [id, name] : {std::pair{"soft-tissue", "Soft tissue"}, std::pair{"fat", "Fat"}}) {
    const ThresholdPreset* preset = FindThresholdPreset(id);
    if (!preset) throw std::runtime_error(std::string("threshold preset ") + id + " missing");
    TissueRecipe recipe;
    recipe.Target = {id, name, preset->TissueClass, preset->Color, false, 0.9};
    recipe.Method.Lower = preset->Lower;
    recipe.Method.Upper = preset->Upper;
    recipe.Edits = {{SegmentEdit::KeepLargest, 0, {}, 1}};
    std::vector<TissueStep> steps;
    if (!logic->SegmentTissue(state.CT, segmentation, recipe, steps, error)) throw std::runtime_error(error);
  }
  state.Segmentation = segmentation;

  state.Runner->Progress(0.4, "meshing");
  // Bones and soft tissue get display and haptic meshes. Fat stays a segment only: a thin
  // shell under the skin gives a large two-sided mesh that neither the planning nor the haptic
  // exploration needs (model no more than the scene needs).
  ModelBuildOptions boneOptions;
  boneOptions.Display.Sigma = 1.0;
  boneOptions.DisplayLOD.TargetTriangles = 120000;
  boneOptions.HapticLOD.TargetTriangles = 30000;
  boneOptions.SegmentIDs = boneIDs;
  ModelBuildOptions softOptions = boneOptions;
  softOptions.SegmentIDs = {"soft-tissue"};
  softOptions.Display.Sigma = 1.5;
  for (double& step : softOptions.Display.GridStep) step = 2.0;  // large and smooth: a 2-voxel grid
  softOptions.DisplayLOD.TargetTriangles = 0;
  auto built = logic->CreateModels(segmentation, boneOptions, StageProgress(state));
  state.Runner->Progress(0.7, "meshing soft tissue");
  const auto soft = logic->CreateModels(segmentation, softOptions, StageProgress(state));
  built.insert(built.end(), soft.begin(), soft.end());
  double bounds[6];
  state.CT->GetRASBounds(bounds);
  for (int a = 0; a < 3; ++a) bounds[2 * a] += 3.0, bounds[2 * a + 1] -= 3.0;  // ignore the cut caps
  for (const SegmentModels& m : built) {
    if (!m.Ok) {
      state.Report->AddNote("Segment " + m.Name + ": no model (" + m.Error + ")");
      continue;
    }
    if (m.DisplayModel) {
      state.DisplayModelIDs.push_back(m.DisplayModel->GetID());
      state.DisplayModelIDOfSegment[m.SegmentID] = m.DisplayModel->GetID();
    }
    // Soft tissue is drawn see-through so the bones stay visible inside it.
    if (m.DisplayModel && m.TissueClass != "bone") m.DisplayModel->SetOpacity(0.25);
    if (m.HapticModel) state.HapticModelIDs.push_back(m.HapticModel->GetID());
    const bool isBone = m.TissueClass == "bone";
    if (isBone && m.DisplayModel) state.BoneModelIDs.push_back(m.DisplayModel->GetID());
    state.Report->AddFigureBelow(stage, m.Name + ": mesh volume vs labelmap", std::abs(m.Display.VolumeErrorPercent), "%", 1.0);
    state.Report->AddFigure(stage, m.Name + ": display / haptic triangles", double(m.Display.Triangles), "",
                            std::to_string(m.Haptic.Triangles) + " haptic triangles, " +
                                (m.Display.Watertight && (!m.HapticModel || m.Haptic.Watertight) ? "watertight" : "NOT watertight"));
  }
  state.Report->AddPictureIf(DemoScreenshot(state, nullptr, "", "segmentation-4up.png", error), stage,
                             "segmentation-4up.png",
                             "4-up of the segmented knee: bone and soft-tissue models with the CT slices in 3D, "
                             "segment outlines on the slices.",
                             error);
  state.Report->AddPictureIf(DemoBoneViews(state, state.BoneModelIDs, "bones-3d.png", error), stage, "bones-3d.png",
                             "The segmented bones as a surgeon looks at the knee: from the front and from the lateral "
                             "side, each bone in its colour (display meshes).",
                             error);
  ScoreSegmentedBones(state, built, bounds, stage);
}

}  // namespace

std::vector<DemoStage> DemoStages() {
  return {
      {"Knee phantom (CT, PD-MR, ground truth)", GeneratePhantom},
      {"DICOM series out and back in", DicomRoundTrip},
      {"CT↔MR registration (Mattes MI)", RegisterCTAndMR},
      {"Segmentation (bones, soft tissue, fat) and meshes", SegmentAndMesh},
      {"Stylus pivot calibration (simulated Polaris, serial protocol on a pty)", CalibrateStylus},
      {"Patient-to-image registration (digitized landmarks)", RegisterPatient},
      {"Navigation: scripted tool path, re-slicing at the tip", Navigate},
      {"Haptic exploration at 1 kHz (simulated device)", ExploreHaptically},
      {"Plan: tibial tunnel (proposed entry) and a screw, checked against the CT", PlanTunnelAndScrew},
      {"Tibial tunnel drilled at 1 kHz (the plan, on a voxel tibia, structures at risk protected)", DrillTibialTunnel},
      {"The plan executed three ways (free hand, guided, guided with forbidden regions)", ExecutePlans},
      {"Speed against accuracy (this patient, against the VTK way)", MeasureSpeedAgainstAccuracy},
  };
}

}  // namespace rp
