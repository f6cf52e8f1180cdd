// Displayable managers and the view controller without Qt: nodes added appear, modified update,
// removed disappear; slices follow the slice point and a tracked tool; outlines match the
// analytic cut of a sphere.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkAlgorithm.h>
#include <vtkAlgorithmOutput.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMapper.h>
#include <vtkCamera.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkActor2DCollection.h>
#include <vtkCoordinate.h>
#include <vtkTextActor.h>
#include <algorithm>
#include <array>
#include <utility>
#include <vector>
#include <string>

#include "rpView.h"
#include "rpViewController.h"
#include "rpViewerTestScene.h"
#include "rpXDisplay.h"
#include "vtkRPCachedRenderPass.h"
#include "vtkRPPlanDisplayableManager.h"
#include "vtkRPTrajectoryNode.h"
#include "vtkRPFiducialDisplayableManager.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelDisplayableManager.h"
#include "vtkRPModelNode.h"
#include "vtkRPModelSliceDisplayableManager.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"
#include "vtkRPToolDisplayableManager.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPViewState.h"
#include "vtkRPViewportImageActor.h"
#include "vtkRPVolumeSliceDisplayableManager.h"

using namespace rp;

namespace {

// RGBA of a slice node's picture at a RAS point on its plane.
void SampleSlice(vtkRPSliceLogic* logic, const double ras[3], unsigned char rgba[4]) {
  vtkAlgorithm* producer = logic->GetOutputPort()->GetProducer();
  producer->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(producer->GetOutputDataObject(0));
  ASSERT_NE(image, nullptr);
  vtkNew<vtkMatrix4x4> rasToSlice;
  vtkMatrix4x4::Invert(logic->GetPlaneToRAS(), rasToSlice);
  double in[4] = {ras[0], ras[1], ras[2], 1}, slice[4];
  rasToSlice->MultiplyPoint(in, slice);
  int ijk[3];
  double pcoords[3];
  ASSERT_TRUE(image->ComputeStructuredCoordinates(slice, ijk, pcoords)) << "point outside the slice image";
  const double spacing = logic->GetPixelSpacing();
  double origin[3];
  image->GetOrigin(origin);
  const int i = static_cast<int>(std::lround((slice[0] - origin[0]) / spacing));
  const int j = static_cast<int>(std::lround((slice[1] - origin[1]) / spacing));
  auto* pixel = static_cast<unsigned char*>(image->GetScalarPointer(i, j, 0));
  for (int c = 0; c < 4; ++c) rgba[c] = pixel[c];
}

// An offscreen window for one view, no multisampling (pixels are compared exactly).
vtkSmartPointer<vtkRenderWindow> OffscreenWindow(int width, int height) {
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  std::string error;
  if (!rp::PrepareOffscreenWindow(window, error)) ADD_FAILURE() << error;
  window->SetMultiSamples(0);
  window->SetSize(width, height);
  return window;
}

// The RGB of the window pixel where a RAS point lands in a view.
void PixelAt(View* view, vtkRenderWindow* window, const double ras[3], unsigned char rgb[3]) {
  double display[2];
  view->RASToDisplay(ras, display);
  const int x = static_cast<int>(display[0]), y = static_cast<int>(display[1]);
  const int* size = window->GetSize();
  ASSERT_TRUE(x >= 0 && x < size[0] && y >= 0 && y < size[1]) << "the point is outside the window";
  unsigned char* data = window->GetPixelData(x, y, x, y, 1);
  std::copy(data, data + 3, rgb);
  delete[] data;
}

}  // namespace

TEST(ViewerDisplayableManagers, VolumeSlicesFollowTheSlicePointAndWindowLevel) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto volume = test::MakeVolume();
  scene->AddNode(volume);
  // First volume: the background of every slice node, slices centred on it.
  for (int kind = 0; kind < 3; ++kind) {
    EXPECT_EQ(controller.GetSliceNode(static_cast<ViewKind>(kind))->GetBackgroundVolumeID(), volume->GetID());
  }
  double point[3];
  controller.GetSlicePointRAS(point);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(point[a], test::Center[a], 1e-9);

  auto* axialManager = controller.GetView(ViewKind::Axial)->GetDisplayableManager<vtkRPVolumeSliceDisplayableManager>();
  ASSERT_NE(axialManager, nullptr);
  EXPECT_EQ(axialManager->GetNumberOfVisibleSlices(), 1);
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);
  EXPECT_TRUE(axial->HasImage());
  EXPECT_NE(axialManager->GetScreenPictureActor(), nullptr);  // drawn at the view's pixels
  EXPECT_EQ(axialManager->GetSliceActor(0), nullptr);
  // The plane passes through the slice point: SliceToRAS translation is the S offset.
  EXPECT_NEAR(axial->GetPlaneToRAS()->GetElement(2, 3), test::Center[2], 1e-9);

  // Window 2000 / level 500 (-500..1500): the ball (1000 HU) is 0.75 of the way → ~191;
  // soft tissue at the centre slice (k = 15.5 → 102 HU) → (102 + 500) / 2000 → ~77.
  unsigned char rgba[4];
  SampleSlice(axial, test::Center, rgba);
  EXPECT_NEAR(rgba[0], 0.75 * 255, 1.5);
  EXPECT_EQ(rgba[3], 255);
  const double tissue[3] = {test::Center[0] + 40, test::Center[1] + 30, test::Center[2]};
  SampleSlice(axial, tissue, rgba);
  const double hu = 40 + 4 * 15.5;  // linear interpolation between slices 15 and 16
  EXPECT_NEAR(rgba[0], (hu + 500) / 2000.0 * 255, 2.0);

  // Window/level live in the node: changing it updates the slices.
  volume->SetWindowLevel(200, 1000);  // 900..1100: the ball mid-grey, tissue black
  SampleSlice(axial, test::Center, rgba);
  EXPECT_NEAR(rgba[0], 0.5 * 255, 1.5);
  SampleSlice(axial, tissue, rgba);
  EXPECT_EQ(rgba[0], 0);

  // Presets.
  EXPECT_TRUE(controller.ApplyWindowLevelPreset(WindowLevelPreset::CTBone));
  EXPECT_DOUBLE_EQ(volume->GetWindow(), 1000);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), 400);
  EXPECT_TRUE(controller.ApplyWindowLevelPreset(WindowLevelPreset::CTSoftTissue));
  EXPECT_DOUBLE_EQ(volume->GetWindow(), 400);
  EXPECT_DOUBLE_EQ(volume->GetLevel(), 40);
  EXPECT_TRUE(controller.ApplyWindowLevelPreset(WindowLevelPreset::MR));
  EXPECT_GT(volume->GetWindow(), 0);
  EXPECT_LE(volume->GetLevel(), 1000);

  // Moving the slice point moves the sagittal plane to the new R.
  const double moved[3] = {test::Center[0] + 12, test::Center[1] - 6, test::Center[2] + 5};
  controller.SetSlicePointRAS(moved);
  vtkRPSliceLogic* sagittal = controller.GetSliceLogic(ViewKind::Sagittal);
  EXPECT_NEAR(sagittal->GetPlaneToRAS()->GetElement(0, 3), moved[0], 1e-9);
  EXPECT_NEAR(controller.GetView(ViewKind::Coronal)->GetSliceOffset(), moved[1], 1e-9);
  // Scrolling: one step is the smallest spacing (2 mm).
  controller.MoveSlice(ViewKind::Axial, 3);
  controller.GetSlicePointRAS(point);
  EXPECT_NEAR(point[2], moved[2] + 3 * 2.0, 1e-9);

  // 3D: the same three pictures in RAS (re-sliced once for both views); off per slice node.
  auto* threeD = controller.GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPVolumeSliceDisplayableManager>();
  EXPECT_EQ(threeD->GetNumberOfVisibleSlices(), 3);
  EXPECT_EQ(threeD->GetSliceActor(0)->GetUserMatrix(), axial->GetPlaneToRAS());
  controller.GetSliceNode(ViewKind::Coronal)->SetSliceVisible(false);
  EXPECT_EQ(threeD->GetNumberOfVisibleSlices(), 2);
  EXPECT_FALSE(threeD->GetSliceActor(2)->GetVisibility());
  controller.SetSlicesVisibleIn3D(true);
  EXPECT_EQ(threeD->GetNumberOfVisibleSlices(), 3);

  // Removed: the background is cleared and the slices disappear.
  scene->RemoveNode(volume);
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Axial)->GetBackgroundVolumeID(), "");
  EXPECT_EQ(controller.GetBackgroundVolume(), nullptr);
  EXPECT_EQ(axialManager->GetNumberOfVisibleSlices(), 0);
  EXPECT_EQ(threeD->GetNumberOfVisibleSlices(), 0);
}

// A slice view draws its picture resampled at its own pixels (vtkRPViewportImageActor): the
// pixel under a RAS point shows the picture's colour there, in a viewport that does not start at
// the window's corner, after a zoom and a pan too; black where the plane leaves the volume; a
// render with nothing changed re-uses the uploaded picture.
TEST(ViewerDisplayableManagers, TheSliceViewShowsItsPictureAtItsOwnPixels) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  auto window = OffscreenWindow(400, 260);
  const double right[4] = {0.5, 0, 1, 1};
  View* view = controller.GetView(ViewKind::Axial);
  view->AttachToRenderWindow(window, right);
  view->ResetCamera();
  window->Render();
  auto* manager = view->GetDisplayableManager<vtkRPVolumeSliceDisplayableManager>();
  ASSERT_NE(manager, nullptr);
  vtkRPViewportImageActor* actor = manager->GetScreenPictureActor();
  ASSERT_NE(actor, nullptr);
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);

  auto pixelAt = [&](const double ras[3], unsigned char rgb[3]) {
    double display[2];
    view->RASToDisplay(ras, display);
    ASSERT_GE(display[0], 200) << "the point is not in the view's viewport (the window's right half)";
    PixelAt(view, window, ras, rgb);
  };
  const double ball[3] = {test::Center[0] + 5, test::Center[1] - 4, test::Center[2]};
  const double tissue[3] = {test::Center[0] + 30, test::Center[1] + 30, test::Center[2]};  // in view after the zoom
  // Beyond the volume (±40 mm in A), inside the view, off the crosshair (which passes the centre).
  const double air[3] = {test::Center[0] + 20, test::Center[1] + 45, test::Center[2]};
  for (int pass = 0; pass < 2; ++pass) {
    for (const double* ras : {ball, tissue}) {
      unsigned char expected[4] = {0, 0, 0, 0}, shown[3] = {0, 0, 0};
      SampleSlice(axial, ras, expected);
      pixelAt(ras, shown);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], expected[c], 2.0) << "pass " << pass << " channel " << c;
    }
    unsigned char shown[3] = {1, 1, 1};
    pixelAt(air, shown);
    EXPECT_EQ(shown[0] + shown[1] + shown[2], 0) << "pass " << pass;
    // Zoomed in and panned: the same points, at other pixels, the same colours.
    const double pan[3] = {-3.0, 4.0, 0.0};
    view->Zoom(1.3);
    view->Pan(pan);
    window->Render();
  }
  const int uploads = actor->GetNumberOfUploads();
  window->Render();  // nothing changed
  EXPECT_EQ(actor->GetNumberOfUploads(), uploads);
  EXPECT_GT(actor->GetNumberOfDraws(), 2);
  view->DetachFromRenderWindow();
}

namespace {
// A CT and an "MR" (the test volume twice), added in that order: the MR becomes the foreground.
std::pair<vtkSmartPointer<vtkRPScalarVolumeNode>, vtkSmartPointer<vtkRPScalarVolumeNode>> AddCTAndMR(vtkRPScene* scene) {
  auto ct = test::MakeVolume();
  scene->AddNode(ct);
  auto mr = test::MakeVolume();
  mr->SetName("MR");
  scene->AddNode(mr);
  return {ct, mr};
}
}  // namespace

TEST(ViewerDisplayableManagers, ForegroundBlendsOverBackground) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto [ct, mr] = AddCTAndMR(scene);
  mr->SetWindowLevel(1, 2000);  // everything at or below 2000 is black in the MR
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Axial)->GetForegroundVolumeID(), mr->GetID());
  controller.SetForegroundOpacity(0.5);
  ct->SetWindowLevel(1, 0);  // everything above 0 is white in the CT
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);
  unsigned char rgba[4];
  SampleSlice(axial, test::Center, rgba);
  EXPECT_NEAR(rgba[0], 127.5, 1.5);  // white under black at 50 %
  controller.SetForegroundOpacity(0.0);
  SampleSlice(axial, test::Center, rgba);
  EXPECT_EQ(rgba[0], 255);
}

// The picture made ahead on a worker thread (StartPicture, as the render scheduler does for the
// views after the first) is the picture made when the view updates, byte for byte; a slice moved
// while one is being made gives the new plane's picture, not the old one.
TEST(ViewerDisplayableManagers, APictureMadeAheadIsThePictureMadeOnDemand) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  AddCTAndMR(scene);
  controller.SetForegroundOpacity(0.4);
  vtkRPSliceLogic* sagittal = controller.GetSliceLogic(ViewKind::Sagittal);
  // A second logic on the same node makes its pictures on demand only.
  vtkNew<vtkRPSliceLogic> onDemand;
  onDemand->SetSliceNode(scene, controller.GetSliceNode(ViewKind::Sagittal));
  auto picture = [](vtkRPSliceLogic* logic) {
    vtkAlgorithm* producer = logic->GetOutputPort()->GetProducer();
    producer->Update();
    auto* image = vtkImageData::SafeDownCast(producer->GetOutputDataObject(0));
    auto* bytes = static_cast<const unsigned char*>(image->GetScalarPointer());
    return std::vector<unsigned char>(bytes, bytes + 4 * image->GetNumberOfPoints());
  };
  double point[3] = {test::Center[0] + 3.3, test::Center[1] - 2.1, test::Center[2] + 1.7};
  for (int step = 0; step < 3; ++step) {
    point[0] += 1.37;
    controller.SetSlicePointRAS(point);
    const int before = sagittal->GetNumberOfReslices();
    const int aheadBefore = sagittal->GetNumberOfPicturesMadeAhead();
    sagittal->StartPicture();
    if (step == 2) {
      // Moved again while the picture is being made: the started one is for the old plane.
      point[0] += 2.1;
      controller.SetSlicePointRAS(point);
    }
    const auto ahead = picture(sagittal);
    const auto made = picture(onDemand);
    ASSERT_FALSE(made.empty());
    EXPECT_EQ(ahead, made) << "step " << step;
    EXPECT_EQ(sagittal->GetNumberOfReslices(), before + 1) << "one picture per change, step " << step;
    EXPECT_EQ(sagittal->GetNumberOfPicturesMadeAhead(), aheadBefore + (step == 2 ? 0 : 1))
        << "the picture made ahead is used unless the plane moved since, step " << step;
    sagittal->StartPicture();  // up to date: starts nothing
    sagittal->WaitForPicture();
    EXPECT_EQ(sagittal->GetNumberOfReslices(), before + 1);
  }
}

TEST(ViewerDisplayableManagers, ModelsAppearUpdateAndDisappear) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto* models = controller.GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPModelDisplayableManager>();
  View* axialView = controller.GetView(ViewKind::Axial);
  auto* outlines = axialView->GetDisplayableManager<vtkRPModelSliceDisplayableManager>();
  ASSERT_NE(models, nullptr);
  ASSERT_NE(outlines, nullptr);
  auto model = test::MakeSphereModel();
  scene->AddNode(model);
  vtkActor* actor = models->GetActor(model);
  ASSERT_NE(actor, nullptr);
  EXPECT_TRUE(actor->GetVisibility());
  EXPECT_DOUBLE_EQ(actor->GetProperty()->GetColor()[0], 0.9);

  // Axial outline through the sphere at S = 20 + 12: a circle of radius sqrt(20² − 12²) = 16
  // around (ModelCenter R, A).
  const double point[3] = {0, 0, test::ModelCenter[2] + 12};
  controller.SetSlicePointRAS(point);
  vtkPolyData* outline = outlines->GetOutline(model);
  ASSERT_NE(outline, nullptr);
  ASSERT_GT(outline->GetNumberOfPoints(), 32);
  for (vtkIdType i = 0; i < outline->GetNumberOfPoints(); ++i) {
    double p[3];
    outline->GetPoint(i, p);
    EXPECT_NEAR(p[2], point[2], 1e-6);
    EXPECT_NEAR(std::hypot(p[0] - test::ModelCenter[0], p[1] - test::ModelCenter[1]), 16.0, 0.1);
  }

  // Modified: colour, opacity, visibility, transform.
  axialView->MarkRendered();
  controller.GetView(ViewKind::ThreeD)->MarkRendered();
  model->SetColor(0.2, 0.4, 0.6);
  model->SetOpacity(0.5);
  EXPECT_TRUE(axialView->NeedsRender());
  EXPECT_TRUE(controller.GetView(ViewKind::ThreeD)->NeedsRender());
  EXPECT_DOUBLE_EQ(actor->GetProperty()->GetColor()[2], 0.6);
  EXPECT_DOUBLE_EQ(actor->GetProperty()->GetOpacity(), 0.5);
  model->SetVisibility(false);
  EXPECT_FALSE(actor->GetVisibility());
  EXPECT_EQ(outlines->GetOutline(model), nullptr);
  model->SetVisibility(true);

  // Under a transform moving it 10 mm up: the actor follows and the outline radius becomes
  // sqrt(20² − 2²) at the same slice.
  vtkNew<vtkRPLinearTransformNode> lift;
  scene->AddNode(lift);
  ASSERT_TRUE(model->SetAndObserveTransformNodeID(lift->GetID()));
  vtkNew<vtkMatrix4x4> up;
  up->SetElement(2, 3, 10.0);
  lift->SetMatrixTransformToParent(up);
  EXPECT_DOUBLE_EQ(actor->GetUserMatrix()->GetElement(2, 3), 10.0);
  outline = outlines->GetOutline(model);
  ASSERT_NE(outline, nullptr);
  vtkMatrix4x4* toWorld = up;
  for (vtkIdType i = 0; i < outline->GetNumberOfPoints(); i += 7) {
    double local[4] = {0, 0, 0, 1}, world[4];
    outline->GetPoint(i, local);
    toWorld->MultiplyPoint(local, world);
    EXPECT_NEAR(world[2], point[2], 1e-6);
    EXPECT_NEAR(std::hypot(world[0] - test::ModelCenter[0], world[1] - test::ModelCenter[1]), std::sqrt(400.0 - 4.0), 0.1);
  }

  // Removed: gone from every view.
  scene->RemoveNode(model);
  EXPECT_EQ(models->GetActor(model), nullptr);
  EXPECT_EQ(models->GetNumberOfDisplayedNodes(), 0);
  EXPECT_EQ(outlines->GetNumberOfDisplayedNodes(), 0);
}

TEST(ViewerDisplayableManagers, FiducialsShowOnTheirSliceAndIn3D) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  const double onSlice[3] = {test::Center[0] + 5, test::Center[1] + 3, test::Center[2]};
  auto* list = vtkRPFiducialListNode::SafeDownCast(controller.PlaceFiducial(onSlice));
  ASSERT_NE(list, nullptr);
  EXPECT_EQ(list->GetNumberOfControlPoints(), 1);
  EXPECT_EQ(controller.GetViewState()->GetActiveFiducialListID(), list->GetID());
  auto* axial = controller.GetView(ViewKind::Axial)->GetDisplayableManager<vtkRPFiducialDisplayableManager>();
  auto* threeD = controller.GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPFiducialDisplayableManager>();
  EXPECT_EQ(axial->GetNumberOfDrawnPoints(list), 1);
  EXPECT_EQ(threeD->GetNumberOfDrawnPoints(list), 1);
  controller.MoveSlice(ViewKind::Axial, 5);  // 10 mm away: not on this slice any more
  EXPECT_EQ(axial->GetNumberOfDrawnPoints(list), 0);
  EXPECT_EQ(threeD->GetNumberOfDrawnPoints(list), 1);
  const double second[3] = {1, 2, 3};
  controller.PlaceFiducial(second);
  EXPECT_EQ(list->GetNumberOfControlPoints(), 2);
  EXPECT_EQ(threeD->GetNumberOfDrawnPoints(list), 2);
  scene->RemoveNode(list);
  EXPECT_EQ(threeD->GetNumberOfDisplayedNodes(), 0);
}

// Eight landmarks within 3 mm of each other (a crowded spot): rendered, no label overprints
// another, in the 3D view and in the axial view, and every label is inside its view.
// In 3D each slice is a quad over its picture's patient pixels only: air around a body of radius
// 40 mm is not rasterized (a software renderer pays for every fragment the shader cuts away), and
// the texture coordinates follow, so the body shows where it did with the whole plane drawn.
TEST(ViewerDisplayableManagers, TheSlicesIn3DSpanTheirPatientPixelsOnly) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto volume = test::MakeVolume();
  vtkImageData* image = volume->GetImageData();  // axis-aligned: voxel (i, j) at Center + Spacing · (i − c, j − c)
  int dims[3];
  image->GetDimensions(dims);
  constexpr double Body = 40.0;  // mm from the centre's S axis: air beyond
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const double x = (i - 0.5 * (dims[0] - 1)) * test::Spacing[0], y = (j - 0.5 * (dims[1] - 1)) * test::Spacing[1];
        if (std::hypot(x, y) > Body) *static_cast<short*>(image->GetScalarPointer(i, j, k)) = -1000;
      }
  scene->AddNode(volume);
  auto window = OffscreenWindow(400, 400);
  const double full[4] = {0, 0, 1, 1};
  View* view = controller.GetView(ViewKind::ThreeD);
  view->AttachToRenderWindow(window, full);
  controller.ResetCameras3D();
  window->Render();
  auto* manager = view->GetDisplayableManager<vtkRPVolumeSliceDisplayableManager>();
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);
  const double* plane = axial->GetPlaneBounds();  // pixel centres, plane coordinates (R, A from the centre)
  const double h = 0.5 * axial->GetPixelSpacing();
  double quad[6];
  vtkPolyData::SafeDownCast(manager->GetSliceActor(0)->GetMapper()->GetInput())->GetBounds(quad);
  // The body's disc (around the centre's place on the plane), to within a pixel, not the whole
  // plane of 96 × 80 mm; cut by the plane's edges where it reaches past them.
  vtkNew<vtkMatrix4x4> rasToPlane;
  vtkMatrix4x4::Invert(axial->GetPlaneToRAS(), rasToPlane);
  const double centre[4] = {test::Center[0], test::Center[1], test::Center[2], 1};
  double c[4];
  rasToPlane->MultiplyPoint(centre, c);
  EXPECT_GT(plane[1] - plane[0] + 2 * h, 95.0);
  EXPECT_NEAR(quad[0], std::max(c[0] - Body, plane[0] - h), 2 * h + 1e-6);
  EXPECT_NEAR(quad[1], std::min(c[0] + Body, plane[1] + h), 2 * h + 1e-6);
  EXPECT_NEAR(quad[2], std::max(c[1] - Body, plane[2] - h), 2 * h + 1e-6);
  EXPECT_NEAR(quad[3], std::min(c[1] + Body, plane[3] + h), 2 * h + 1e-6);
  EXPECT_LT(quad[1] - quad[0], plane[1] - plane[0] - 10);
  // Its corners' texture coordinates are those pixels' place in the whole picture.
  vtkDataArray* tcoords = vtkPolyData::SafeDownCast(manager->GetSliceActor(0)->GetMapper()->GetInput())->GetPointData()->GetTCoords();
  ASSERT_NE(tcoords, nullptr);
  const double width = plane[1] - plane[0] + 2 * h;
  EXPECT_NEAR(tcoords->GetComponent(0, 0), (quad[0] - (plane[0] - h)) / width, 1e-6);
  EXPECT_NEAR(tcoords->GetComponent(1, 0), (quad[1] - (plane[0] - h)) / width, 1e-6);
  // The body's centre still shows the slice there (the ball, bright), seen from the front: the
  // coronal slice through the centre faces the camera.
  unsigned char rgb[3];
  PixelAt(view, window, test::Center, rgb);
  EXPECT_GT(rgb[0], 150);
  view->DetachFromRenderWindow();
}

TEST(ViewerDisplayableManagers, FiducialLabelsDoNotOverprint) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  vtkNew<vtkRPFiducialListNode> list;
  for (int i = 0; i < 8; ++i) {
    const double p[3] = {test::Center[0] + 0.4 * i, test::Center[1] - 0.3 * i, test::Center[2]};
    list->AddControlPoint(p, "landmark " + std::to_string(i + 1));
  }
  scene->AddNode(list);
  vtkNew<vtkRenderWindow> window;
  std::string windowError;
  ASSERT_TRUE(rp::PrepareOffscreenWindow(window, windowError)) << windowError;
  window->SetSize(600, 300);
  const double left[4] = {0, 0, 0.5, 1}, right[4] = {0.5, 0, 1, 1};
  controller.GetView(ViewKind::Axial)->AttachToRenderWindow(window, left);
  controller.GetView(ViewKind::ThreeD)->AttachToRenderWindow(window, right);
  controller.ResetCameras3D();
  window->Render();
  for (ViewKind kind : {ViewKind::Axial, ViewKind::ThreeD}) {
    vtkRenderer* renderer = controller.GetView(kind)->GetOverlayRenderer();
    std::vector<std::array<double, 4>> boxes;  // xmin, xmax, ymin, ymax
    vtkActor2DCollection* actors = renderer->GetActors2D();
    actors->InitTraversal();
    while (vtkActor2D* actor = actors->GetNextActor2D()) {
      auto* text = vtkTextActor::SafeDownCast(actor);
      if (!text || !text->GetVisibility() || std::string(text->GetInput()).rfind("landmark", 0) != 0) continue;
      std::array<double, 4> box;
      text->GetBoundingBox(renderer, box.data());
      const double* position = text->GetPositionCoordinate()->GetValue();
      box = {position[0], position[0] + box[1] - box[0], position[1], position[1] + box[3] - box[2]};
      boxes.push_back(box);
    }
    ASSERT_EQ(boxes.size(), 8u) << GetViewName(kind);
    double vp[4];
    renderer->GetViewport(vp);
    for (size_t i = 0; i < boxes.size(); ++i) {
      EXPECT_GE(boxes[i][0], vp[0] * 600 - 1e-6) << GetViewName(kind);
      EXPECT_LE(boxes[i][1], vp[2] * 600 + 1e-6) << GetViewName(kind);
      for (size_t j = 0; j < i; ++j) {
        const bool overlap = boxes[i][0] < boxes[j][1] && boxes[j][0] < boxes[i][1] && boxes[i][2] < boxes[j][3] &&
                             boxes[j][2] < boxes[i][3];
        EXPECT_FALSE(overlap) << GetViewName(kind) << ": label " << i + 1 << " over label " << j + 1;
      }
    }
  }
  for (ViewKind kind : {ViewKind::Axial, ViewKind::ThreeD}) controller.GetView(kind)->DetachFromRenderWindow();
}

TEST(ViewerDisplayableManagers, ToolsAreDrawnAndSlicesFollowTheTip) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;
  trackerToRAS->SetName("TrackerToRAS");
  scene->AddNode(trackerToRAS);
  vtkNew<vtkRPTrackedToolNode> stylus;
  stylus->SetName("StylusToTracker");
  scene->AddNode(stylus);
  ASSERT_TRUE(stylus->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  stylus->SetStatus(vtkRPTrackedToolNode::StatusOK);

  auto* tools = controller.GetView(ViewKind::ThreeD)->GetDisplayableManager<vtkRPToolDisplayableManager>();
  auto* sliceTools = controller.GetView(ViewKind::Coronal)->GetDisplayableManager<vtkRPToolDisplayableManager>();
  ASSERT_NE(tools->GetGlyphActor(stylus), nullptr);
  ASSERT_NE(sliceTools->GetGlyphActor(stylus), nullptr);
  EXPECT_EQ(tools->GetGlyphActor(trackerToRAS), nullptr);  // plain transform: no glyph
  EXPECT_EQ(tools->GetForceActor(stylus), nullptr);

  controller.SetFollowTransformNodeID(stylus->GetID());
  vtkNew<vtkMatrix4x4> pose;
  pose->SetElement(0, 3, 4.0);
  pose->SetElement(1, 3, -7.0);
  pose->SetElement(2, 3, 12.0);
  stylus->SetMatrixTransformToParent(pose);
  double point[3];
  controller.GetSlicePointRAS(point);
  EXPECT_DOUBLE_EQ(point[0], 4.0);
  EXPECT_DOUBLE_EQ(point[1], -7.0);
  EXPECT_DOUBLE_EQ(point[2], 12.0);
  EXPECT_DOUBLE_EQ(tools->GetGlyphActor(stylus)->GetUserMatrix()->GetElement(1, 3), -7.0);

  // A parent moving (registration updated) moves the tip and the slices.
  vtkNew<vtkMatrix4x4> shift;
  shift->SetElement(2, 3, 100.0);
  trackerToRAS->SetMatrixTransformToParent(shift);
  controller.GetSlicePointRAS(point);
  EXPECT_DOUBLE_EQ(point[2], 112.0);
  EXPECT_DOUBLE_EQ(tools->GetGlyphActor(stylus)->GetUserMatrix()->GetElement(2, 3), 112.0);

  // Force arrow from attributes: 2 N along +R at 10 mm/N → a 20 mm arrow from the tip.
  stylus->SetAttribute("Viewer.Force", "2,0,0");
  vtkActor* arrow = tools->GetForceActor(stylus);
  ASSERT_NE(arrow, nullptr);
  EXPECT_NEAR(arrow->GetUserMatrix()->GetElement(0, 0), 20.0, 1e-9);
  EXPECT_NEAR(arrow->GetUserMatrix()->GetElement(2, 3), 112.0, 1e-9);
  stylus->SetAttribute("Viewer.Force", "0,0,0");
  EXPECT_EQ(tools->GetForceActor(stylus), nullptr);

  // A proxy sphere on any transform node through the attribute.
  trackerToRAS->SetAttribute("Viewer.Glyph", "sphere");
  EXPECT_NE(tools->GetGlyphActor(trackerToRAS), nullptr);

  // The Haptics module's proxy: a tool node with a "Force" attribute → sphere + arrow.
  vtkNew<vtkRPTrackedToolNode> proxy;
  proxy->SetName("HapticProxy");
  proxy->SetAttribute("Force", "0,0,-1.5");
  scene->AddNode(proxy);
  vtkActor* proxyArrow = tools->GetForceActor(proxy);
  ASSERT_NE(proxyArrow, nullptr);
  EXPECT_NEAR(proxyArrow->GetUserMatrix()->GetElement(2, 0), -15.0, 1e-9);  // 1.5 N × 10 mm/N, along −S
  ASSERT_NE(tools->GetGlyphActor(proxy), nullptr);
  double proxyBounds[6];
  tools->GetGlyphActor(proxy)->GetMapper()->GetBounds(proxyBounds);
  EXPECT_NEAR(proxyBounds[5] - proxyBounds[4], 4.0, 0.1);  // a 2 mm sphere, not an 80 mm stylus

  // A tool the tracker lost is drawn faded.
  stylus->SetStatus(vtkRPTrackedToolNode::StatusMissing);
  EXPECT_LT(tools->GetGlyphActor(stylus)->GetProperty()->GetOpacity(), 1.0);

  // Removing the followed node stops following and removes the glyph.
  scene->RemoveNode(stylus);
  EXPECT_EQ(controller.GetFollowTransformNodeID(), "");
  EXPECT_EQ(tools->GetGlyphActor(stylus), nullptr);
}

TEST(ViewerDisplayableManagers, SegmentationsOverlayTheSlicesInSegmentColours) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  // Labelmap 20^3 at 1 mm from RAS (0, 0, 0): label 2 in the box i, j, k in [5, 9].
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(20, 20, 20);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* voxels = static_cast<unsigned char*>(labels->GetScalarPointer());
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) *voxels++ = (i >= 5 && i <= 9 && j >= 5 && j <= 9 && k >= 5 && k <= 9) ? 2 : 0;
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetImageData(labels);
  vtkRPSegmentationNode::Segment bone;
  bone.ID = "bone";
  bone.Name = "Bone";
  bone.LabelValue = 2;
  bone.Color[0] = 1;
  bone.Color[1] = 0;
  bone.Color[2] = 0;
  segmentation->SetSegment(bone);
  scene->AddNode(segmentation);
  // The segmentation is the slice nodes' label layer, composited into the slice pictures.
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Axial)->GetLabelNodeID(), segmentation->GetID());
  controller.GetSliceNode(ViewKind::Axial)->SetLabelOpacity(1.0);
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);
  const double inside[3] = {7, 7, 7};
  controller.SetSlicePointRAS(inside);
  unsigned char rgba[4];
  SampleSlice(axial, inside, rgba);
  EXPECT_EQ(rgba[0], 255);  // the segment's red, opaque at label opacity 1
  EXPECT_EQ(rgba[1], 0);
  EXPECT_EQ(rgba[3], 255);
  const double besideR[3] = {2, 7, 7}, besideA[3] = {7, 12, 7};  // label 0: the CT's grey shows
  SampleSlice(axial, besideR, rgba);
  EXPECT_EQ(rgba[0], rgba[1]);
  SampleSlice(axial, besideA, rgba);
  EXPECT_EQ(rgba[0], rgba[1]);
  // At half opacity: half red over the grey.
  controller.GetSliceNode(ViewKind::Axial)->SetLabelOpacity(0.5);
  SampleSlice(axial, besideR, rgba);
  const int grey = rgba[0];
  SampleSlice(axial, inside, rgba);
  EXPECT_NEAR(rgba[0], 0.5 * grey + 0.5 * 255, 2);
  EXPECT_NEAR(rgba[1], 0.5 * grey, 2);
  // Off the box along S: nothing on this slice.
  const double above[3] = {7, 7, 12};
  controller.SetSlicePointRAS(above);
  SampleSlice(axial, above, rgba);
  EXPECT_EQ(rgba[0], rgba[1]);
  // Removed: the label layer is cleared.
  scene->RemoveNode(segmentation);
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Axial)->GetLabelNodeID(), "");
  SampleSlice(axial, above, rgba);
  EXPECT_EQ(rgba[0], rgba[1]);
}

TEST(ViewerDisplayableManagers, ClosingTheSceneEmptiesEveryViewAndAViewMayOutliveItsScene) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  test::AddVolumeAndModel(scene);
  vtkNew<vtkRPTrackedToolNode> tool;
  scene->AddNode(tool);
  controller.SetFollowTransformNodeID(tool->GetID());
  scene->Clear();
  for (int kind = 0; kind < 4; ++kind) {
    for (const auto& manager : controller.GetView(static_cast<ViewKind>(kind))->GetDisplayableManagers()) {
      EXPECT_EQ(manager->GetNumberOfDisplayedNodes(), 0) << manager->GetClassName();
    }
  }
  EXPECT_EQ(controller.GetSliceNode(ViewKind::Axial)->GetBackgroundVolumeID(), "");
  EXPECT_EQ(controller.GetFollowTransformNodeID(), "");
  EXPECT_EQ(vtkRPSliceNode::GetSliceNodes(scene).size(), 3u);  // the views' nodes stay

  // A controller whose scene (and its followed node) is deleted first shuts down cleanly.
  auto* shortLived = vtkRPScene::New();
  auto later = std::make_unique<ViewController>(shortLived);
  test::AddVolumeAndModel(shortLived);
  auto* followed = vtkRPLinearTransformNode::New();  // owned by the scene only
  shortLived->AddNode(followed);
  followed->Delete();
  later->SetFollowTransformNodeID(followed->GetID());
  shortLived->Delete();
  EXPECT_EQ(later->GetBackgroundVolume(), nullptr);
  later.reset();
}

// Placing a landmark on a model in the 3D view: the ray under the pixel of a known surface point
// hits the sphere there.
TEST(ViewerDisplayableManagers, ClickIn3DPlacesAFiducialOnTheModelSurface) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto model = test::MakeSphereModel();
  scene->AddNode(model);
  vtkNew<vtkRenderWindow> window;
  std::string windowError;
  ASSERT_TRUE(rp::PrepareOffscreenWindow(window, windowError)) << windowError;
  window->SetSize(300, 300);
  const double full[4] = {0, 0, 1, 1};
  View* view = controller.GetView(ViewKind::ThreeD);
  view->AttachToRenderWindow(window, full);
  view->ResetCamera();
  window->Render();
  // The sphere point facing the camera.
  double position[3], towardsCamera[3];
  view->GetRenderer()->GetActiveCamera()->GetPosition(position);
  for (int a = 0; a < 3; ++a) towardsCamera[a] = position[a] - test::ModelCenter[a];
  vtkMath::Normalize(towardsCamera);
  double surface[3], display[2];
  for (int a = 0; a < 3; ++a) surface[a] = test::ModelCenter[a] + test::SphereRadius * towardsCamera[a];
  view->RASToDisplay(surface, display);

  EXPECT_FALSE(controller.ClickIn3DView(display[0], display[1]));  // navigating: no placement
  controller.GetViewState()->SetInteractionMode(vtkRPViewState::ModePlaceFiducial);
  ASSERT_TRUE(controller.ClickIn3DView(display[0], display[1]));
  auto* list = vtkRPFiducialListNode::SafeDownCast(scene->GetNodeByID(controller.GetViewState()->GetActiveFiducialListID()));
  ASSERT_NE(list, nullptr);
  double placed[3];
  list->GetNthControlPointPosition(0, placed);
  EXPECT_NEAR(std::sqrt(vtkMath::Distance2BetweenPoints(placed, test::ModelCenter)), test::SphereRadius, 0.2);
  EXPECT_LT(std::sqrt(vtkMath::Distance2BetweenPoints(placed, surface)), 1.0);
  // Off the model: nothing hit, nothing placed.
  EXPECT_FALSE(controller.ClickIn3DView(2, 2));
  EXPECT_EQ(list->GetNumberOfControlPoints(), 1);
  view->DetachFromRenderWindow();
}

// The 3D view keeps the models' picture while only a tool moves: the frame copies it (colour and
// depth) and draws the tool over it, and what it shows is what rendering everything shows —
// the tool at its new place, hidden behind the opaque model, seen beside it.
TEST(ViewerDisplayableManagers, The3DViewKeepsTheModelsPictureWhileAToolMoves) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  auto model = test::MakeSphereModel();
  model->SetColor(0.0, 0.0, 1.0);
  scene->AddNode(model);
  vtkNew<vtkRPLinearTransformNode> tool;
  tool->SetName("Tip");
  tool->SetAttribute("Viewer.Glyph", "sphere");
  tool->SetAttribute("Viewer.GlyphRadius", "6");
  tool->SetAttribute("Viewer.Color", "1,0,0");
  scene->AddNode(tool);
  auto window = OffscreenWindow(240, 240);
  const double full[4] = {0, 0, 1, 1};
  View* view = controller.GetView(ViewKind::ThreeD);
  view->AttachToRenderWindow(window, full);
  view->ResetCamera();
  vtkRPCachedRenderPass* models = view->GetModelLayerPass();
  ASSERT_NE(models, nullptr);
  ASSERT_TRUE(view->GetModelLayerCaching());

  auto pixelAt = [&](const double ras[3], unsigned char rgb[3]) { PixelAt(view, window, ras, rgb); };
  auto moveTool = [&](const double ras[3]) {
    vtkNew<vtkMatrix4x4> pose;
    for (int a = 0; a < 3; ++a) pose->SetElement(a, 3, ras[a]);
    tool->SetMatrixTransformToParent(pose);
  };
  auto picture = [&]() {
    const int* size = window->GetSize();
    unsigned char* data = window->GetPixelData(0, 0, size[0] - 1, size[1] - 1, 1);
    std::vector<unsigned char> bytes(data, data + 3 * size[0] * size[1]);
    delete[] data;
    return bytes;
  };

  // Beside the sphere (up and to the patient's right of it, seen from the front): the tool is seen.
  const double beside[3] = {test::ModelCenter[0] + 21, test::ModelCenter[1], test::ModelCenter[2] + 21};
  moveTool(beside);
  window->Render();
  const int rendersBefore = models->GetNumberOfRenders();
  unsigned char rgb[3];
  pixelAt(beside, rgb);
  EXPECT_GT(rgb[0], 150);
  EXPECT_LT(rgb[2], 80);

  // Behind it (posterior): a copied frame; the kept depth hides the tool behind the model.
  const double behind[3] = {test::ModelCenter[0], test::ModelCenter[1] - 2 * test::SphereRadius, test::ModelCenter[2]};
  moveTool(behind);
  window->Render();
  EXPECT_EQ(models->GetNumberOfRenders(), rendersBefore);
  EXPECT_FALSE(models->GetLastFrameRendered());
  pixelAt(behind, rgb);
  EXPECT_LT(rgb[0], 60) << "the tool shows through the opaque model";
  EXPECT_GT(rgb[2], 100);
  pixelAt(beside, rgb);
  EXPECT_GT(rgb[2], 150) << "the tool's old place still shows it, not the background";
  const std::vector<unsigned char> copied = picture();

  // The same frame with every model drawn again: the same pixels.
  view->SetModelLayerCaching(false);
  window->Render();
  EXPECT_TRUE(models->GetLastFrameRendered());
  EXPECT_EQ(picture(), copied);
  view->SetModelLayerCaching(true);

  // A model changing (its colour) is drawn again; so is a turned camera.
  window->Render();
  const int renders = models->GetNumberOfRenders();
  window->Render();
  EXPECT_EQ(models->GetNumberOfRenders(), renders);
  model->SetColor(0.0, 1.0, 0.0);
  window->Render();
  EXPECT_EQ(models->GetNumberOfRenders(), renders + 1);
  const double centre[3] = {test::ModelCenter[0], test::ModelCenter[1], test::ModelCenter[2]};
  pixelAt(centre, rgb);
  EXPECT_GT(rgb[1], 100);
  EXPECT_LT(rgb[2], 60);
  view->GetRenderer()->GetActiveCamera()->Azimuth(30);
  window->Render();
  EXPECT_EQ(models->GetNumberOfRenders(), renders + 2);
  // The camera turning tick after tick: the models are drawn light; once only the tool moves
  // again (the kept picture copied), they are whole.
  view->SetInteractive(true);
  EXPECT_TRUE(view->GetInteractive());
  view->SetInteractive(false);
  window->Render();
  moveTool(beside);
  window->Render();
  EXPECT_FALSE(models->GetLastFrameRendered());
  view->SetInteractive(true);
  EXPECT_FALSE(view->GetInteractive());
  view->DetachFromRenderWindow();
}

TEST(ViewerDisplayableManagers, EmptyVolumesShowNothingAndDoNotCrash) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  vtkNew<vtkRPScalarVolumeNode> empty;
  vtkNew<vtkImageData> nothing;
  empty->SetImageData(nothing);
  scene->AddNode(empty);
  vtkRPSliceLogic* axial = controller.GetSliceLogic(ViewKind::Axial);
  EXPECT_FALSE(axial->HasImage());
  controller.MoveSlice(ViewKind::Axial, 2);
  EXPECT_FALSE(controller.ApplyWindowLevelPreset(WindowLevelPreset::MR));  // no volume with voxels to show
  controller.AdjustWindowLevel(10, 10);  // ignored
  // A real volume added later becomes the background (the empty one has nothing to show).
  scene->AddNode(test::MakeVolume());
  EXPECT_TRUE(axial->HasImage());
  EXPECT_NE(controller.GetBackgroundVolume(), empty.GetPointer());
}

// A plan is placed and dragged in the views: a new empty trajectory makes the next clicks in a
// slice view its entry and target (then the views go back to navigating); the tool's cylinder is
// drawn in 3D and its outline on the slice; a press on an end drags it in the slice view, and in
// the 3D view onto the model under the cursor.
TEST(ViewerDisplayableManagers, ATrajectoryIsPlacedByClicksAndItsEndsDraggedInSliceAnd3DViews) {
  vtkNew<vtkRPScene> scene;
  ViewController controller(scene);
  scene->AddNode(test::MakeVolume());
  auto model = test::MakeSphereModel();
  scene->AddNode(model);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(600, 300);
  const double left[4] = {0, 0, 0.5, 1}, right[4] = {0.5, 0, 1, 1};
  View* axial = controller.GetView(ViewKind::Axial);
  View* threeD = controller.GetView(ViewKind::ThreeD);
  axial->AttachToRenderWindow(window, left);
  threeD->AttachToRenderWindow(window, right);
  controller.ResetViews();
  window->Render();

  vtkNew<vtkRPTrajectoryNode> tunnel;
  tunnel->SetToolDiameterMm(4);
  scene->AddNode(tunnel);
  EXPECT_EQ(controller.GetViewState()->GetInteractionMode(), vtkRPViewState::ModePlaceFiducial);
  EXPECT_EQ(controller.GetViewState()->GetActiveFiducialListID(), tunnel->GetID());
  const double entry[3] = {test::Center[0] - 20, test::Center[1], test::Center[2]},
               target[3] = {test::Center[0] + 10, test::Center[1] + 5, test::Center[2]};
  double display[2];
  for (const double* point : {entry, target}) {
    axial->RASToDisplay(point, display);
    ASSERT_TRUE(controller.ClickInSliceView(ViewKind::Axial, display[0], display[1]));
  }
  ASSERT_TRUE(tunnel->IsComplete());
  double placed[3];
  tunnel->GetEntryWorld(placed);
  EXPECT_LT(std::sqrt(vtkMath::Distance2BetweenPoints(placed, entry)), 1.0);
  EXPECT_EQ(controller.GetViewState()->GetInteractionMode(), vtkRPViewState::ModeNavigate);  // placed in full
  auto* plans3D = threeD->GetDisplayableManager<vtkRPPlanDisplayableManager>();
  auto* plansAxial = axial->GetDisplayableManager<vtkRPPlanDisplayableManager>();
  ASSERT_NE(plans3D->GetDrawnGeometry(tunnel), nullptr);
  EXPECT_GT(plans3D->GetDrawnGeometry(tunnel)->GetNumberOfCells(), 24);  // the cylinder
  ASSERT_NE(plansAxial->GetDrawnGeometry(tunnel), nullptr);  // its outline and projected axis
  EXPECT_GT(plansAxial->GetDrawnGeometry(tunnel)->GetNumberOfLines(), 2);

  // Drag the entry in the slice view.
  axial->RASToDisplay(entry, display);
  std::string id;
  int index = -1;
  ASSERT_TRUE(controller.FindFiducialAt(ViewKind::Axial, display[0], display[1], 6, id, index));
  EXPECT_EQ(id, tunnel->GetID());
  EXPECT_EQ(index, vtkRPTrajectoryNode::EntryIndex);
  const double moved[3] = {entry[0], entry[1] + 8, entry[2]};
  ASSERT_TRUE(controller.MoveFiducial(id, index, moved));
  tunnel->GetEntryWorld(placed);
  EXPECT_NEAR(placed[1], entry[1] + 8, 1e-9);

  // Drag the target in 3D onto the model's surface facing the camera.
  window->Render();
  tunnel->GetTargetWorld(placed);
  threeD->RASToDisplay(placed, display);
  ASSERT_TRUE(controller.FindControlPointIn3D(display[0], display[1], 6, id, index));
  EXPECT_EQ(index, vtkRPTrajectoryNode::TargetIndex);
  double camera[3], towards[3], surface[3];
  threeD->GetRenderer()->GetActiveCamera()->GetPosition(camera);
  for (int a = 0; a < 3; ++a) towards[a] = camera[a] - test::ModelCenter[a];
  vtkMath::Normalize(towards);
  for (int a = 0; a < 3; ++a) surface[a] = test::ModelCenter[a] + test::SphereRadius * towards[a];
  threeD->RASToDisplay(surface, display);
  ASSERT_TRUE(controller.DragControlPointIn3D(id, index, display[0], display[1]));
  tunnel->GetTargetWorld(placed);
  EXPECT_NEAR(std::sqrt(vtkMath::Distance2BetweenPoints(placed, test::ModelCenter)), test::SphereRadius, 0.5);
  axial->DetachFromRenderWindow();
  threeD->DetachFromRenderWindow();
}
