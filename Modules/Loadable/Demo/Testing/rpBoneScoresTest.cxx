// Per-bone scoring against closed-form answers: two boxes of voxels as truth bones, segments
// shifted by a known number of voxels (Dice 1 - shift/length), matched by overlap whatever
// their names, a soft-tissue segment never taken for a bone, the truth on another grid.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpBoneScores.h"
#include "rpImageVolume.h"
#include "rpLabelmapToMesh.h"
#include "vtkRPSegmentationNode.h"

namespace {

constexpr int N = 40;  // 40³ voxels of 1 mm, IJK = RAS

// Box [x0, x1) × [y0, y1) × [z0, z1) in voxels.
struct Box {
  int Lo[3], Hi[3];
  bool Has(int i, int j, int k) const {
    return i >= Lo[0] && i < Hi[0] && j >= Lo[1] && j < Hi[1] && k >= Lo[2] && k < Hi[2];
  }
};

vtkSmartPointer<vtkImageData> Labels(const std::vector<std::pair<Box, unsigned char>>& boxes, int n = N) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        unsigned char l = 0;
        for (const auto& [box, label] : boxes)
          if (box.Has(i, j, k)) l = label;
        *v++ = l;
      }
  return image;
}

}  // namespace

TEST(BoneScores, DiceAndSurfaceDistanceOfShiftedBoxesMatchedByOverlap) {
  // Truth: label 1 = box A (10 voxels along x), label 2 = box B.
  const Box a{{5, 5, 5}, {15, 15, 15}}, b{{22, 8, 8}, {32, 18, 18}};
  rp::ImageVolume truth;
  truth.Image = Labels({{a, 1}, {b, 2}});
  // Segments: "Bone 7" = A shifted by 2 voxels along x, "Bone 3" = B exactly, "Soft tissue" covers
  // everything else around A (more of A's voxels than any bone segment would, if it counted).
  const Box a2{{7, 5, 5}, {17, 15, 15}};
  const Box soft{{0, 0, 0}, {21, 21, 21}};
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetImageData(Labels({{soft, 5}, {a2, 7}, {b, 3}}));
  vtkNew<vtkMatrix4x4> identity;
  segmentation->SetIJKToRASMatrix(identity);
  auto add = [&](const char* id, const char* name, int label, const char* tissue) {
    rp::Segment s;
    s.ID = id;
    s.Name = name;
    s.LabelValue = label;
    s.TissueClass = tissue;
    segmentation->SetSegment(s);
  };
  add("soft", "Soft tissue", 5, "muscle");
  add("b7", "Bone 7", 7, "bone");
  add("b3", "Bone 3", 3, "bone");

  std::string error;
  const auto bones = rp::LabelmapTruthBones(truth, {"", "tibia", "fibula"}, segmentation, error);
  ASSERT_EQ(bones.size(), 2u) << error;
  EXPECT_EQ(bones[0].Name, "tibia");
  EXPECT_EQ(bones[1].Name, "fibula");
  // Meshes of the segments, as the demo makes them.
  std::map<std::string, vtkSmartPointer<vtkPolyData>> meshes;
  for (const auto& [id, label] : std::vector<std::pair<std::string, int>>{{"b7", 7}, {"b3", 3}}) {
    auto mesh = vtkSmartPointer<vtkPolyData>::New();
    rp::MeshStats stats;
    ASSERT_TRUE(rp::LabelmapToMesh(segmentation->GetImageData(), identity, label, rp::MeshOptions{}, mesh, stats, error))
        << error;
    meshes[id] = mesh;
  }
  const double everywhere[6] = {-1, N, -1, N, -1, N};
  const auto scores = rp::ScoreBones(
      bones, segmentation, [&](const std::string& id) -> vtkPolyData* { return meshes.count(id) ? meshes[id].Get() : nullptr; },
      everywhere);
  ASSERT_EQ(scores.size(), 2u);
  // Tibia ↔ Bone 7 (not the soft tissue that overlaps it wholly): Dice = 2·8·10·10 / 2000 = 0.8.
  EXPECT_EQ(scores[0].SegmentName, "Bone 7");
  EXPECT_NEAR(scores[0].Dice, 0.8, 1e-12);
  ASSERT_TRUE(scores[0].HasSurface);
  // Two faces of the box moved by 2 mm, four faces in place (up to 2 mm): the mean lies between.
  EXPECT_GT(scores[0].Surface.MeanMm, 0.3);
  EXPECT_LT(scores[0].Surface.MeanMm, 1.5);
  EXPECT_NEAR(scores[0].Surface.HausdorffMm, 2.0, 0.5);
  // Fibula ↔ Bone 3, the same voxels: Dice 1 and the same surface.
  EXPECT_EQ(scores[1].SegmentName, "Bone 3");
  EXPECT_DOUBLE_EQ(scores[1].Dice, 1.0);
  EXPECT_LT(scores[1].Surface.MeanMm, 0.05);
  EXPECT_LT(scores[1].Surface.Percentile95Mm, 0.1);
}

TEST(BoneScores, TruthOnAnotherGridAndBonesNoSegmentReaches) {
  // The truth at 2 mm voxels (20³) covering the same space: box A is voxels 3..7 → 6..15 mm.
  rp::ImageVolume truth;
  truth.Image = Labels({{Box{{3, 3, 3}, {8, 8, 8}}, 1}, {Box{{15, 15, 15}, {18, 18, 18}}, 2}}, 20);
  truth.IJKToRAS->Identity();
  for (int a = 0; a < 3; ++a) truth.IJKToRAS->SetElement(a, a, 2.0);
  vtkNew<vtkRPSegmentationNode> segmentation;
  const Box a{{5, 5, 5}, {15, 15, 15}};  // voxel centres 5..14 mm → nearest truth voxels 3..7 (2 mm)
  segmentation->SetImageData(Labels({{a, 1}}));
  vtkNew<vtkMatrix4x4> identity;
  segmentation->SetIJKToRASMatrix(identity);
  rp::Segment s;
  s.ID = "femur";
  s.Name = "Femur";
  s.LabelValue = 1;
  s.TissueClass = "bone";
  segmentation->SetSegment(s);
  std::string error;
  const auto bones = rp::LabelmapTruthBones(truth, {}, segmentation, error);
  ASSERT_EQ(bones.size(), 2u) << error;
  EXPECT_EQ(bones[0].Name, "label 1");
  const double everywhere[6] = {-1, N, -1, N, -1, N};
  const auto scores = rp::ScoreBones(bones, segmentation, [](const std::string&) { return nullptr; }, everywhere);
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(scores[0].SegmentID, "femur");
  EXPECT_NEAR(scores[0].Dice, 1.0, 1e-12);
  EXPECT_FALSE(scores[0].HasSurface);  // no mesh given
  EXPECT_TRUE(scores[1].SegmentID.empty());  // nothing segmented there
  EXPECT_EQ(scores[1].Dice, 0.0);
  // An empty truth is refused with a message.
  rp::ImageVolume empty;
  empty.Image = Labels({}, 4);
  EXPECT_TRUE(rp::LabelmapTruthBones(empty, {}, segmentation, error).empty());
  EXPECT_NE(error.find("no labelled voxel"), std::string::npos) << error;
}
