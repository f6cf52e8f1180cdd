// Whether the demo can draw, and its pictures (the scene rendered, an image slice): drawn by
// libRoboPlanDemoPictures.so (Pictures/, rpDemoPictures.h), loaded on the first one, so that the
// demo's logic maps no Qt, no VTK rendering and no image codecs until it draws.
#include <filesystem>

#include "rpBenchmarkChart.h"
#include "rpDemoPictures.h"
#include "rpDemoStages.h"
#include "rpReport.h"
#include "rpSiblingLibrary.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {

namespace {

/// The entry `symbol` of libRoboPlanDemoPictures.so (beside this library); nullptr with `error`
/// naming the library's path and why.
template <typename Function>
Function PicturesEntry(const char* symbol, const std::string& file, std::string& error) {
  std::string why;
  const auto function = SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&PicturesEntry<Function>),
                                                         demo_pictures::Library, symbol, why);
  if (!function) error = "picture '" + file + "' not drawn: " + why;
  return function;
}

}  // namespace

bool CanDrawPictures(const DemoState& state, std::string& error) {
  if (!state.Options.Screenshots) {
    error = "screenshots turned off (--no-screenshots)";
    return false;
  }
  // $DISPLAY when it answers, else a private Xvfb; once for the run (rpXDisplay.h).
  return bench::OpenDrawingDisplay(error);
}

bool CanDrawPicturesOrWarn(DemoState& state, const std::string& stage, const std::string& what) {
  std::string why;
  if (CanDrawPictures(state, why)) return true;
  if (state.Options.Screenshots)
    state.Report->AddMissingPicture(stage, what, why);
  else
    state.Report->AddNote(what + " skipped: " + why + ".");
  return false;
}

bool DemoScreenshot(DemoState& state, const double slicePointRAS[3], const std::string& followNodeID,
                    const std::string& file, std::string& error) {
  if (!CanDrawPictures(state, error)) return false;
  const auto draw = PicturesEntry<demo_pictures::FourUpFunction>(demo_pictures::FourUpEntry, file, error);
  if (!draw) return false;
  demo_pictures::FourUp picture;
  picture.Scene = state.Scene;
  if (state.CT) picture.BackgroundID = state.CT->GetID();
  if (state.MR) picture.ForegroundID = state.MR->GetID();
  picture.FollowNodeID = followNodeID;
  picture.HasSlicePoint = slicePointRAS != nullptr;
  if (slicePointRAS)
    for (int i = 0; i < 3; ++i) picture.SlicePointRAS[static_cast<size_t>(i)] = slicePointRAS[i];
  return draw(picture, (fs::path(state.Output) / file).string(), error);
}

bool DemoBoneViews(DemoState& state, const std::vector<std::string>& modelIDs, const std::string& file,
                   std::string& error) {
  if (!CanDrawPictures(state, error)) return false;
  const auto draw = PicturesEntry<demo_pictures::BoneViewsFunction>(demo_pictures::BoneViewsEntry, file, error);
  if (!draw) return false;
  demo_pictures::BoneViews picture;
  picture.Scene = state.Scene;
  picture.ModelIDs = modelIDs;
  picture.Lateral = state.KneeLateral;
  picture.Anterior = state.KneeAnterior;
  picture.AxesKnown = state.KneeAxesKnown;
  return draw(picture, (fs::path(state.Output) / file).string(), error);
}

bool DemoSlicePicture(DemoState& state, vtkImageData* slice, double window, double level, const std::string& file,
                      std::string& error) {
  const auto draw = PicturesEntry<demo_pictures::SliceFunction>(demo_pictures::SliceEntry, file, error);
  if (!draw) return false;
  demo_pictures::Slice picture;
  picture.Image = slice;
  picture.Window = window;
  picture.Level = level;
  return draw(picture, (fs::path(state.Output) / file).string(), error);
}

}  // namespace rp
