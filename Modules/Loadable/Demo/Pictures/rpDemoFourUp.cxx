// The 4-up pictures of the scene for the report, through the viewer's own offscreen rendering (the
// same displayable managers as the Qt views). Part of libRoboPlanDemoPictures.so (rpDemoPictures.h);
// only builds with the viewer (GUI on) can draw them.
#include "rpDemoPictures.h"

#ifdef ROBOPLAN_WORKFLOW_HAVE_VIEWER
#include "rpScreenshot.h"
#include "rpViewController.h"
#include "vtkRPLayoutNode.h"
#endif

RP_DEMO_PICTURES_ENTRY bool roboplan_demo_four_up(const rp::demo_pictures::FourUp& picture, const std::string& path,
                                                  std::string& error) {
#ifdef ROBOPLAN_WORKFLOW_HAVE_VIEWER
  rp::ViewController controller(picture.Scene);
  if (!picture.BackgroundID.empty()) controller.SetBackgroundVolumeID(picture.BackgroundID);
  if (!picture.ForegroundID.empty()) {
    controller.SetForegroundVolumeID(picture.ForegroundID);
    controller.SetForegroundOpacity(0.35);
  }
  controller.ResetViews();
  if (!picture.FollowNodeID.empty()) controller.SetFollowTransformNodeID(picture.FollowNodeID);
  if (picture.HasSlicePoint) controller.SetSlicePointRAS(picture.SlicePointRAS.data());
  rp::ScreenshotOptions options;
  options.Width = 1400;
  options.Height = 1100;
  options.Layout = vtkRPLayoutNode::FourUp;
  if (picture.HasSlicePoint) {
    options.HasSlicePoint = true;
    for (int i = 0; i < 3; ++i) options.SlicePointRAS[i] = picture.SlicePointRAS[static_cast<size_t>(i)];
  }
  return rp::SaveScreenshot(controller, path, options, error);
#else
  (void)picture;
  (void)path;
  error = "this build has no viewer (ROBOPLAN_BUILD_GUI=OFF)";
  return false;
#endif
}
