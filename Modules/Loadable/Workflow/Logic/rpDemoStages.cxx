#include "rpDemoStages.h"

#include <filesystem>
#include <stdexcept>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpImageVolume.h"
#include "rpKneePhantom.h"
#include "rpReport.h"
#include "rpVolumeIO.h"
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

}  // namespace

std::vector<DemoStage> DemoStages() {
  return {
      {"Knee phantom (CT, PD-MR, ground truth)", GeneratePhantom},
  };
}

}  // namespace rp
