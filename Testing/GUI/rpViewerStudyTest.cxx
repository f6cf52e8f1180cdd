// A study opens whole (issue 42), through the one loader and the headless screenshot, on the real
// knee CT with a DICOM SEG and an RTSTRUCT of its bone labels (Testing/Support/rpKneeStudy.h):
// - the folder gives the CT and both segmentations, each referencing the CT; the screenshot shows
//   the CT with the labels' colours over the bones in every slice view;
// - the folder's files shuffled (other names, so another order) give the same scene and picture;
// - a segmentation alone (.seg.nrrd, or the SEG file) is visible: every slice view and the 3D view
//   show its labels in its colours (a test that fails on black views).
// Each picture's share of non-black pixels per view is printed (the closing note's figures).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>

#include "rpDataLoader.h"
#include "rpImagingReaders.h"
#include "rpKneeStudy.h"
#include "rpScreenshot.h"
#include "rpView.h"
#include "rpViewController.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"

namespace fs = std::filesystem;
using namespace rp;

namespace {

constexpr int Size = 800;  // the 4-up picture, 400 x 400 pixels a view

// The study, made once for the tests of this program.
const rp::testing::KneeStudy* Study(std::string& skip) {
  static rp::testing::KneeStudy study;
  static std::string problem = [] {
    if (!fs::exists(rptest::SharedDataPath("knee-ct-vhf/dicom"))) return std::string("shared data absent");
    if (!rp::testing::HavePydicom()) return std::string("pydicom (python3-pydicom) not installed: no RTSTRUCT writer");
    std::string error;
    return rp::testing::MakeKneeStudy(fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "knee-study", study, error) ? std::string() : error;
  }();
  skip = problem;
  return problem.empty() ? &study : nullptr;
}

#define REQUIRE_STUDY(study)                                                               \
  std::string skip_;                                                                       \
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");                                             \
  const rp::testing::KneeStudy* study = Study(skip_);                                          \
  if (!study && skip_.find("pydicom") != std::string::npos) GTEST_SKIP() << skip_;         \
  ASSERT_NE(study, nullptr) << skip_

struct Picture {
  vtkNew<vtkImageData> Image;
  const unsigned char* At(int x, int y) const {  // y from the bottom (VTK)
    return static_cast<const unsigned char*>(this->Image->GetScalarPointer(x, y, 0));
  }
};

bool Render(vtkRPScene* scene, Picture& picture, const std::string& png) {
  ViewController controller(scene);
  ScreenshotOptions options;
  options.Width = options.Height = Size;
  options.Layout = vtkRPLayoutNode::FourUp;
  std::string error;
  if (!RenderViews(controller, options, picture.Image, error)) {
    ADD_FAILURE() << error;
    return false;
  }
  fs::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName((fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / png).c_str());
  writer->SetInputData(picture.Image);
  writer->Write();
  return true;
}

// The views of the 4-up picture: name and pixel box (x0, y0, x1, y1; y from the bottom).
struct ViewBox {
  const char* Name;
  int X0, Y0, X1, Y1;
};
const std::array<ViewBox, 4> Views = {{{"axial", 0, Size / 2, Size / 2, Size},
                                       {"3D", Size / 2, Size / 2, Size, Size},
                                       {"sagittal", 0, 0, Size / 2, Size / 2},
                                       {"coronal", Size / 2, 0, Size, Size / 2}}};

// What a view shows of one label: pixels of its colour (alone: the colour itself; over the CT:
// the colour at the label opacity over a grey), and the mean grey under them.
struct LabelPixels {
  long Count = 0;
  double GreyUnder = 0;
};

LabelPixels CountLabel(const Picture& picture, const ViewBox& view, const std::array<int, 3>& color, double opacity) {
  LabelPixels found;
  for (int y = view.Y0; y < view.Y1; ++y)
    for (int x = view.X0; x < view.X1; ++x) {
      const unsigned char* p = picture.At(x, y);
      double grey[3];
      for (int c = 0; c < 3; ++c) grey[c] = opacity < 1 ? (p[c] - opacity * color[c]) / (1 - opacity) : 0.0;
      const bool match = opacity < 1 ? std::max({grey[0], grey[1], grey[2]}) - std::min({grey[0], grey[1], grey[2]}) <= 8 &&
                                           std::min({grey[0], grey[1], grey[2]}) >= -6
                                     : std::abs(p[0] - color[0]) <= 4 && std::abs(p[1] - color[1]) <= 4 &&
                                           std::abs(p[2] - color[2]) <= 4;
      if (!match) continue;
      ++found.Count;
      found.GreyUnder += (grey[0] + grey[1] + grey[2]) / 3;
    }
  if (found.Count) found.GreyUnder /= double(found.Count);
  return found;
}

// The share of pixels that are not black (any channel above 8), per view.
double NonBlackShare(const Picture& picture, const ViewBox& view) {
  long count = 0;
  for (int y = view.Y0; y < view.Y1; ++y)
    for (int x = view.X0; x < view.X1; ++x) {
      const unsigned char* p = picture.At(x, y);
      count += p[0] > 8 || p[1] > 8 || p[2] > 8;
    }
  return double(count) / ((view.X1 - view.X0) * (view.Y1 - view.Y0));
}

void PrintShares(const Picture& picture, const std::string& what) {
  std::cout << what << ": non-black share per view";
  for (const ViewBox& view : Views) std::cout << "  " << view.Name << " " << 100.0 * NonBlackShare(picture, view) << " %";
  std::cout << "\n";
}

// The mean grey of the slice view's patient pixels that no label covers (soft tissue and bone).
double MeanGrey(const Picture& picture, const ViewBox& view) {
  double sum = 0;
  long count = 0;
  for (int y = view.Y0; y < view.Y1; ++y)
    for (int x = view.X0; x < view.X1; ++x) {
      const unsigned char* p = picture.At(x, y);
      if (p[0] == p[1] && p[1] == p[2] && p[0] > 8) {
        sum += p[0];
        ++count;
      }
    }
  return count ? sum / count : 0.0;
}

// Every node of a scene that is data (not a view's), by name: class, dimensions and voxels.
std::map<std::string, std::string> Describe(vtkRPScene* scene) {
  std::map<std::string, std::string> nodes;
  for (vtkRPNode* node : scene->GetNodes()) {
    auto* image = vtkRPImageNode::SafeDownCast(node);
    if (!image) continue;
    int dims[3];
    image->GetImageData()->GetDimensions(dims);
    vtkDataArray* scalars = image->GetImageData()->GetPointData()->GetScalars();
    double sum = 0;
    for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i) sum += scalars->GetComponent(i, 0) * double(i % 977 + 1);
    std::string text = std::string(node->GetClassName()) + " " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
                       "x" + std::to_string(dims[2]) + " checksum " + std::to_string(sum);
    if (auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node)) {
      vtkRPNode* on = segmentation->GetNodeReference(vtkRPSegmentationNode::ReferenceImageGeometryRole());
      text += " on " + (on ? on->GetName() : std::string("nothing"));
      for (const auto& s : segmentation->GetSegments()) text += " | " + s.Name;
    }
    nodes[node->GetName()] = text;
  }
  return nodes;
}

}  // namespace

TEST(ViewerStudy, FolderOpensWholeWithTheLabelsOverTheBonesInEveryView) {
  REQUIRE_STUDY(study);
  ASSERT_TRUE(RegisterImagingReaders());
  vtkNew<vtkRPScene> scene;
  const LoadResult load = LoadPath(scene, study->Folder.string());
  ASSERT_TRUE(load.Ok) << load.Error;
  for (const auto& w : load.Warnings) ADD_FAILURE() << "unexpected warning: " << w;
  // The node list: the CT and both segmentations, each on the CT.
  ASSERT_EQ(scene->GetNodesByClass("vtkRPScalarVolumeNode").size(), 1u);
  ASSERT_EQ(scene->GetNodesByClass("vtkRPSegmentationNode").size(), 2u);
  auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodesByClass("vtkRPScalarVolumeNode")[0]);
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode")) {
    auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node);
    EXPECT_EQ(segmentation->GetNodeReference(vtkRPSegmentationNode::ReferenceImageGeometryRole()), ct) << node->GetName();
    ASSERT_EQ(segmentation->GetNumberOfSegments(), 3) << node->GetName();
    for (int s = 0; s < 3; ++s) {
      EXPECT_EQ(segmentation->GetNthSegment(s).Name, rp::testing::KneeLabels()[static_cast<size_t>(s)].Name);
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(std::lround(255 * segmentation->GetNthSegment(s).Color[c]),
                  rp::testing::KneeLabels()[static_cast<size_t>(s)].Color[static_cast<size_t>(c)])
            << node->GetName() << " segment " << s;
    }
  }
  // The views: the CT as background, a segmentation as the label layer.
  Picture picture;
  ASSERT_TRUE(Render(scene, picture, "study-4up.png"));
  PrintShares(picture, "CT + SEG + RTSTRUCT folder");
  for (vtkRPSliceNode* node : vtkRPSliceNode::GetSliceNodes(scene)) {
    EXPECT_EQ(node->GetBackgroundVolumeID(), ct->GetID()) << node->GetLayoutName();
    EXPECT_FALSE(node->GetLabelNodeID().empty()) << node->GetLayoutName();
  }
  const double opacity = vtkRPSliceNode::GetSliceNodes(scene)[0]->GetLabelOpacity();
  for (const ViewBox& view : Views) {
    if (std::string(view.Name) == "3D") continue;
    // The tibia (the bone the whole crop holds) in its colour over bright CT: bone, not soft tissue.
    const LabelPixels tibia = CountLabel(picture, view, rp::testing::KneeLabels()[0].Color, opacity);
    EXPECT_GT(tibia.Count, 2000) << view.Name;
    EXPECT_GT(tibia.GreyUnder, MeanGrey(picture, view) + 20) << view.Name << ": the label is not over bone";
    EXPECT_GT(NonBlackShare(picture, view), 0.2) << view.Name;
  }
}

TEST(ViewerStudy, ShuffledFilesGiveTheSameScene) {
  REQUIRE_STUDY(study);
  ASSERT_TRUE(RegisterImagingReaders());
  // The same files under shuffled names: the folder is read in another order.
  const fs::path shuffled = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "shuffled";
  fs::remove_all(shuffled);
  fs::create_directories(shuffled);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(study->Folder)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<size_t> order(files.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(42));
  for (size_t i = 0; i < files.size(); ++i) fs::copy_file(files[order[i]], shuffled / ("im" + std::to_string(i) + ".dcm"));
  // The segmentations come first in the new order (their files were last).
  vtkNew<vtkRPScene> a, b;
  ASSERT_TRUE(LoadPath(a, study->Folder.string()).Ok);
  const LoadResult load = LoadPath(b, shuffled.string());
  ASSERT_TRUE(load.Ok) << load.Error;
  EXPECT_EQ(Describe(a), Describe(b));
  Picture first, second;
  ASSERT_TRUE(Render(a, first, "study-4up-a.png"));
  ASSERT_TRUE(Render(b, second, "study-4up-shuffled.png"));
  long differing = 0;
  for (int y = 0; y < Size; ++y)
    for (int x = 0; x < Size; ++x)
      differing += !std::equal(first.At(x, y), first.At(x, y) + 3, second.At(x, y));
  EXPECT_EQ(differing, 0) << "the shuffled folder's picture differs";
}

// A segmentation alone: every slice view and the 3D view show its labels (fails on black views).
TEST(ViewerStudy, SegmentationAloneIsVisibleInEveryView) {
  REQUIRE_STUDY(study);
  ASSERT_TRUE(RegisterImagingReaders());
  for (const fs::path& path : {study->SegNrrd, study->Seg}) {
    vtkNew<vtkRPScene> scene;
    const LoadResult load = LoadPath(scene, path.string());
    ASSERT_TRUE(load.Ok) << load.Error;
    ASSERT_EQ(load.Nodes.size(), 1u);
    auto* segmentation = vtkRPSegmentationNode::SafeDownCast(load.Nodes[0]);
    ASSERT_NE(segmentation, nullptr);
    Picture picture;
    ASSERT_TRUE(Render(scene, picture, path.filename().string() + "-4up.png"));
    PrintShares(picture, path.filename().string() + " alone");
    // The slices through the middle of its labelled voxels (their RAS box, counted here).
    double box[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300}, point[3];
    vtkImageData* labels = segmentation->GetImageData();
    int dims[3];
    labels->GetDimensions(dims);
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          if (labels->GetScalarComponentAsDouble(i, j, k, 0) == 0) continue;
          const double ijk[4] = {double(i), double(j), double(k), 1};
          double ras[4];
          segmentation->GetIJKToRASMatrix()->MultiplyPoint(ijk, ras);
          for (int a = 0; a < 3; ++a) box[2 * a] = std::min(box[2 * a], ras[a]), box[2 * a + 1] = std::max(box[2 * a + 1], ras[a]);
        }
    ViewController controller(scene);
    controller.GetSlicePointRAS(point);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(point[a], 0.5 * (box[2 * a] + box[2 * a + 1]), 1e-6) << path;
    for (const ViewBox& view : Views) {
      const bool threeD = std::string(view.Name) == "3D";
      const LabelPixels tibia = CountLabel(picture, view, rp::testing::KneeLabels()[0].Color, 1.0);
      EXPECT_GT(tibia.Count, threeD ? 500 : 2000) << path.filename() << " " << view.Name << ": no tibia in its colour";
      if (!threeD) {
        EXPECT_GT(NonBlackShare(picture, view), 0.05) << path.filename() << " " << view.Name;
      }
    }
  }
}
