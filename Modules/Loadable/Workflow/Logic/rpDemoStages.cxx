#include "rpDemoStages.h"

#include <algorithm>
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

#include "rpDicomSeries.h"
#include "rpDicomWriter.h"
#include "rpImageVolume.h"
#include "rpKneePhantom.h"
#include "rpReport.h"
#include "rpVolumeIO.h"
#include "rpVolumeRegistration.h"
#include "vtkRPLinearTransformNode.h"
#include "rpStageRunner.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

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
    // Between the test and benchmark sizes: fine enough for bone and ligaments, fast on 2 cores.
    options.CTDimensions = {192, 192, 128};
    options.CTSpacing = {0.8, 0.8, 1.25};
  } else {
    throw std::runtime_error("unknown phantom size '" + state.Options.PhantomSize + "' (small, demo, full)");
  }
  auto phantom = std::make_shared<KneePhantom>();
  std::string error;
  if (!GenerateKneePhantom(options, *phantom, error, StageProgress(state))) {
    throw std::runtime_error("knee phantom: " + error);
  }
  state.Phantom = phantom;
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
    DicomScanResult scan;
    if (!ScanDicom(state.Options.DicomData, scan, error, StageProgress(state))) throw std::runtime_error(error);
    const DicomSeriesInfo* chosen = nullptr;
    for (const auto& series : scan.Series) {
      if (series.Problem.empty() && (!chosen || series.Files.size() > chosen->Files.size())) chosen = &series;
    }
    if (!chosen) throw std::runtime_error("no loadable image series in '" + state.Options.DicomData + "'");
    ImageVolume ct;
    std::vector<std::string> warnings;
    if (!ReadDicomSeries(*chosen, ct, error, {}, &warnings, StageProgress(state))) throw std::runtime_error(error);
    for (const auto& w : warnings) state.Report->AddNote("DICOM: " + w);
    state.CT = AddVolumeNode(state, ct, "CT");
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
  if (!WriteDicomSeries(state.Phantom->CT, ctFolder, options, error, &written, StageProgress(state))) {
    throw std::runtime_error("writing the CT series: " + error);
  }
  options.Modality = "MR";
  options.SeriesDescription = "RoboPlan knee phantom PD MR";
  options.SeriesNumber = 2;
  options.StudyInstanceUID = written.StudyInstanceUID;  // one study, two series
  if (!WriteDicomSeries(state.Phantom->MR, mrFolder, options, error, nullptr, StageProgress(state))) {
    throw std::runtime_error("writing the MR series: " + error);
  }
  ImageVolume ct, mr;
  if (!ReadDicomVolume(ctFolder, ct, error)) throw std::runtime_error("reading the CT series back: " + error);
  if (!ReadDicomVolume(mrFolder, mr, error)) throw std::runtime_error("reading the MR series back: " + error);
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
  // Speed over the last tenth of a millimetre: the finest level is skipped (the half-resolution
  // level already lands well under the 1 mm target on the phantom) and fewer voxels sampled.
  options.ShrinkFactors = {4, 2};
  options.SmoothingSigmasMM = {2.0, 1.0};
  options.SamplingFraction = 0.1;
  options.MaxIterationsPerLevel = 100;
  RigidRegistrationResult result;
  std::string error;
  const ImageVolume fixed = FromNode(state.CT), moving = FromNode(state.MR);
  if (!RegisterVolumesRigid(fixed, moving, options, result, error, StageProgress(state))) {
    throw std::runtime_error(error);
  }
  if (!result.Converged) throw std::runtime_error("did not converge: " + result.StopReason);
  // MR sits under MRToCT: the transform node's "to parent" matrix is moving → fixed.
  vtkNew<vtkRPLinearTransformNode> mrToCT;
  mrToCT->SetName("MRToCT");
  mrToCT->SetMatrixTransformToParent(result.MovingToFixed);
  state.Scene->AddNode(mrToCT);
  state.MR->SetAndObserveTransformNodeID(mrToCT->GetID());
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

}  // namespace

std::vector<DemoStage> DemoStages() {
  return {
      {"Knee phantom (CT, PD-MR, ground truth)", GeneratePhantom},
      {"DICOM series out and back in", DicomRoundTrip},
      {"CT↔MR registration (Mattes MI)", RegisterCTAndMR},
  };
}

}  // namespace rp
