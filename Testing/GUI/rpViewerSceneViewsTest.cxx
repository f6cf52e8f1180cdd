// The views are scene state: a change to a slice node (as a module makes it) moves the rendered
// slice; a saved scene reopens with its slices and layout; the 3D view of a real CT with a bone
// model meshed from it shows the model large, seen from the front, with the slices' air cut away.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>

#include "rpImagingReaders.h"
#include "rpSceneIO.h"
#include "rpScreenshot.h"
#include "rpSharedData.h"
#include "rpView.h"
#include "rpViewController.h"
#include "rpViewerApplication.h"
#include "rpViewerTestScene.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"

using namespace rp;

namespace {

const unsigned char* Pixel(vtkImageData* image, int x, int y) {  // y from the bottom (VTK)
  return static_cast<const unsigned char*>(image->GetScalarPointer(x, y, 0));
}

void Save(vtkImageData* image, const std::string& name) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName((std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/" + name).c_str());
  writer->SetInputData(image);
  writer->Write();
}

// The synthetic CT's soft tissue at S (mm): 40 HU + 4 HU per 2.5 mm slice from the first slice.
double TissueHU(double s) {
  const double first = test::Center[2] - 0.5 * (test::Dimensions[2] - 1) * test::Spacing[2];
  return 40 + 4 * (s - first) / test::Spacing[2];
}

// Grey of HU at window 200 / level 120 (the soft tissue's range).
double Grey(double hu) { return std::clamp((hu - 20) / 200.0, 0.0, 1.0) * 255; }

// Width (pixels) of the bright ball along a row of a one-up slice image.
int BallWidth(vtkImageData* image, int row) {
  int dims[3];
  image->GetDimensions(dims);
  int first = -1, last = -1;
  for (int x = 0; x < dims[0]; ++x) {
    if (Pixel(image, x, row)[0] > 180 && Pixel(image, x, row)[2] > 180) {  // grey-white, not the outline
      if (first < 0) first = x;
      last = x;
    }
  }
  return first < 0 ? 0 : last - first + 1;
}

}  // namespace

// A module changes the Red slice node (no view pointer, only the scene): the axial picture shows
// the new plane, with the grey of the tissue there and the ball's smaller cross-section.
TEST(ViewerSceneViews, AModuleMovesTheRenderedSliceThroughTheScene) {
  vtkNew<vtkRPScene> scene;
  auto volume = test::MakeVolume();
  volume->SetWindowLevel(200, 120);
  scene->AddNode(volume);
  ViewController controller(scene);
  ScreenshotOptions options;
  options.Width = options.Height = 160;
  options.Layout = vtkRPLayoutNode::OneUpAxial;
  vtkNew<vtkImageData> before, after;
  std::string error;
  ASSERT_TRUE(RenderViews(controller, options, before, error)) << error;
  const int tissueX = 150, row = 92;  // 70 px right of the centre: soft tissue, off the crosshair
  EXPECT_NEAR(Pixel(before, tissueX, row)[0], Grey(TissueHU(test::Center[2])), 3.0);
  const int widthBefore = BallWidth(before, row);

  // What a module does: find the view's node in the scene and move it 15 mm up.
  vtkRPSliceNode* red = vtkRPSliceNode::GetSliceNode(scene, "Red");
  ASSERT_NE(red, nullptr);
  const int reslices = controller.GetSliceLogic(ViewKind::Axial)->GetNumberOfReslices();
  red->SetSliceOffset(test::Center[2] + 15);
  EXPECT_TRUE(controller.GetView(ViewKind::Axial)->NeedsRender());
  ASSERT_TRUE(RenderViews(controller, options, after, error)) << error;
  Save(before, "module-axial-before.png");
  Save(after, "module-axial-after.png");
  EXPECT_GT(controller.GetSliceLogic(ViewKind::Axial)->GetNumberOfReslices(), reslices);
  EXPECT_NEAR(Pixel(after, tissueX, row)[0], Grey(TissueHU(test::Center[2] + 15)), 3.0);
  EXPECT_GT(Pixel(after, tissueX, row)[0], Pixel(before, tissueX, row)[0] + 20);
  // The ball's cross-section shrinks from radius 25 to sqrt(25² − 15²) = 20 mm (row 12 px off centre).
  EXPECT_LT(BallWidth(after, row), widthBefore - 8);
  // The other slices did not move (and were not re-sliced for it).
  EXPECT_DOUBLE_EQ(vtkRPSliceNode::GetSliceNode(scene, "Yellow")->GetSliceOffset(), test::Center[0]);
}

// A saved scene reopens as it was saved: slice planes (one of them reformatted to another
// orientation), zoom, pan, layers and the layout; the pictures are the same pixels.
TEST(ViewerSceneViews, ASavedSceneReloadsWithItsSliceLayout) {
  const std::filesystem::path dir = std::filesystem::path(ROBOPLAN_TEST_OUTPUT_DIR) / "saved";
  std::filesystem::remove_all(dir);
  vtkNew<vtkRPScene> scene;
  test::AddVolumeAndModel(scene);
  vtkNew<vtkImageData> saved;
  std::string error;
  ScreenshotOptions options;  // the scene's layout
  options.Width = 240;
  options.Height = 200;
  {
    ViewController controller(scene);
    const double point[3] = {test::Center[0] + 6, test::Center[1] - 4, test::Center[2] + 7.5};
    controller.SetSlicePointRAS(point);
    vtkRPSliceNode* yellow = controller.GetSliceNode(ViewKind::Sagittal);
    yellow->SetOrientationToCoronal();  // Yellow shows a coronal plane now
    yellow->JumpSlice(point);
    controller.GetView(ViewKind::Axial)->Zoom(1.6);
    const double pan[3] = {5, 3, 0};
    controller.GetView(ViewKind::Axial)->Pan(pan);
    controller.SetSlicesVisibleIn3D(false);
    controller.GetLayoutNode()->SetViewArrangement(vtkRPLayoutNode::OneUpAxial);
    ASSERT_TRUE(RenderViews(controller, options, saved, error)) << error;
    ASSERT_TRUE(SaveScene(scene, (dir / "views.rpscene").string(), error)) << error;
  }
  // A fresh viewer on the loaded scene (as `roboplan views.rpscene` does).
  vtkNew<vtkRPScene> loaded;
  ViewController controller(loaded);
  std::string loadError;
  ASSERT_TRUE(LoadSceneOrDataFile(loaded, (dir / "views.rpscene").string(), loadError)) << loadError;
  EXPECT_EQ(controller.GetLayoutNode()->GetViewArrangement(), vtkRPLayoutNode::OneUpAxial);
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Sagittal)->GetOrientation(), "Coronal");
  EXPECT_FALSE(controller.GetSlicesVisibleIn3D());
  double point[3];
  controller.GetSlicePointRAS(point);
  EXPECT_NEAR(point[2], test::Center[2] + 7.5, 1e-9);
  vtkNew<vtkImageData> reloaded;
  ASSERT_TRUE(RenderViews(controller, options, reloaded, error)) << error;
  Save(saved, "saved.png");
  Save(reloaded, "reloaded.png");
  int differing = 0;
  for (int y = 0; y < options.Height; ++y)
    for (int x = 0; x < options.Width; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (std::abs(int(Pixel(saved, x, y)[c]) - int(Pixel(reloaded, x, y)[c])) > 8) {
          ++differing;
          break;
        }
      }
    }
  EXPECT_EQ(differing, 0) << "the reloaded views differ from the saved ones (see " << dir << ")";
}

// The case: `roboplan screenshot <CT> <bone model> --layout 3d` of a real CT had 12–13 %
// of the picture black (the slices' air) and the bones hidden behind it. Now: under 3 % black,
// the bone seen from the front fills a sensible part of the view.
TEST(ViewerSceneViews, ThreeDOfARealCTWithItsBoneModelIsReadable) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  const std::string dicom = rptest::SharedDataPath("knee-ct-vhf/dicom");
  ASSERT_TRUE(rp::RegisterImagingReaders());  // as the viewer module's Setup does
  vtkNew<vtkRPScene> scene;
  std::string error;
  ASSERT_TRUE(LoadSceneOrDataFile(scene, dicom, error)) << error;
  auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodesByClass("vtkRPScalarVolumeNode").at(0));
  ASSERT_NE(ct, nullptr);
  // The bone model meshed from the CT itself: the 300 HU iso-surface, in RAS.
  vtkNew<vtkFlyingEdges3D> surface;
  surface->SetInputData(ct->GetImageData());
  surface->SetValue(0, 300);
  surface->ComputeNormalsOn();
  vtkNew<vtkTransform> ijkToRAS;
  ijkToRAS->SetMatrix(ct->GetIJKToRASMatrix());
  vtkNew<vtkTransformPolyDataFilter> toRAS;
  toRAS->SetTransform(ijkToRAS);
  toRAS->SetInputConnection(surface->GetOutputPort());
  toRAS->Update();
  ASSERT_GT(toRAS->GetOutput()->GetNumberOfPoints(), 1000);
  vtkNew<vtkRPModelNode> bone;
  bone->SetName("Bone");
  bone->SetTissueClass("bone");
  bone->SetColor(0.95, 0.91, 0.80);
  bone->SetPolyData(toRAS->GetOutput());
  scene->AddNode(bone);

  ViewController controller(scene);
  ScreenshotOptions options;
  options.Width = options.Height = 400;
  options.Layout = vtkRPLayoutNode::OneUp3D;
  vtkNew<vtkImageData> withSlices, modelOnly;
  ASSERT_TRUE(RenderViews(controller, options, withSlices, error)) << error;
  controller.SetSlicesVisibleIn3D(false);
  ASSERT_TRUE(RenderViews(controller, options, modelOnly, error)) << error;
  Save(withSlices, "knee-ct-3d.png");
  Save(modelOnly, "knee-ct-3d-model.png");

  // Black: every channel under 20 (the old slices' air was 0,0,0).
  int black = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x) {
      const unsigned char* p = Pixel(withSlices, x, y);
      black += p[0] < 20 && p[1] < 20 && p[2] < 20;
    }
  EXPECT_LT(black / (400.0 * 400.0), 0.03) << black << " black pixels";

  // The model's pixels (not the bluish background, not the marker's corner).
  int xmin = 400, xmax = -1, ymin = 400, ymax = -1, covered = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x) {
      if (x > 300 && y < 100) continue;  // the orientation marker
      const unsigned char* p = Pixel(modelOnly, x, y);
      const bool background = p[2] > p[0] + 15;  // the gradient is blue-grey; bone is warm
      if (background) continue;
      ++covered;
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  ASSERT_GT(covered, 0);
  const double extent = std::max(xmax - xmin + 1, ymax - ymin + 1) / 400.0;
  EXPECT_GT(extent, 0.6) << "the model should fill most of the view";
  EXPECT_LT(extent, 0.98) << "the whole model should be in the view";
  EXPECT_GT(covered / (400.0 * 400.0), 0.12);
  // Seen from the front: the camera looks from anterior (+A) towards posterior, head up.
  double position[3], focal[3];
  vtkCamera* camera = controller.GetView(ViewKind::ThreeD)->GetRenderer()->GetActiveCamera();
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  EXPECT_GT(position[1] - focal[1], 0);
  EXPECT_NEAR(position[0], focal[0], 1e-6);
  EXPECT_NEAR(camera->GetViewUp()[2], 1.0, 1e-9);
}
