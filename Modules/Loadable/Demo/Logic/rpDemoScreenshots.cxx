// 4-up pictures of the scene for the report, through the viewer's own offscreen rendering (the
// same displayable managers as the Qt views). Only in builds with the viewer (GUI on).
#include <cstdlib>
#include <filesystem>

#include "rpDemoStages.h"
#include "rpReport.h"
#include "rpXDisplay.h"

#ifdef ROBOPLAN_WORKFLOW_HAVE_VIEWER
#include "rpScreenshot.h"
#include "rpViewController.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPLayoutNode.h"
#endif

namespace fs = std::filesystem;

namespace rp {

bool CanDrawPictures(const DemoState& state, std::string& error) {
  if (!state.Options.Screenshots) {
    error = "screenshots turned off (--no-screenshots)";
    return false;
  }
  // $DISPLAY when it answers, else a private Xvfb; once for the run (rpXDisplay.h).
  return EnsureXDisplay(error);
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
#ifdef ROBOPLAN_WORKFLOW_HAVE_VIEWER
  ViewController controller(state.Scene);
  if (state.CT) controller.SetBackgroundVolumeID(state.CT->GetID());
  if (state.MR) {
    controller.SetForegroundVolumeID(state.MR->GetID());
    controller.SetForegroundOpacity(0.35);
  }
  controller.ResetViews();
  if (!followNodeID.empty()) controller.SetFollowTransformNodeID(followNodeID);
  if (slicePointRAS) controller.SetSlicePointRAS(slicePointRAS);
  ScreenshotOptions options;
  options.Width = 1400;
  options.Height = 1100;
  options.Layout = vtkRPLayoutNode::FourUp;
  if (slicePointRAS) {
    options.HasSlicePoint = true;
    for (int i = 0; i < 3; ++i) options.SlicePointRAS[i] = slicePointRAS[i];
  }
  return SaveScreenshot(controller, (fs::path(state.Output) / file).string(), options, error);
#else
  (void)slicePointRAS;
  (void)followNodeID;
  (void)file;
  error = "this build has no viewer (ROBOPLAN_BUILD_GUI=OFF)";
  return false;
#endif
}

}  // namespace rp
