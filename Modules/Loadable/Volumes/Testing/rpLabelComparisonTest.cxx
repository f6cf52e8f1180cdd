// Dice and surface distances on boxes whose answers are known in closed form.
#include <filesystem>

#include <gtest/gtest.h>

#include <vtkImageData.h>
#include <vtkNew.h>

#include "rpLabelComparison.h"
#include "rpSegmentationIO.h"
#include "rpVolumeIO.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPVolumesLogic.h"

namespace {

// A labelmap of `dims` voxels with `label` in the box [lo, hi) (voxel indices), spacing `s` mm.
rp::ImageVolume Box(const int dims[3], const int lo[3], const int hi[3], int label, const double s[3],
                    const double origin[3] = nullptr) {
  rp::ImageVolume v;
  v.Image = vtkSmartPointer<vtkImageData>::New();
  v.Image->SetDimensions(dims[0], dims[1], dims[2]);
  v.Image->AllocateScalars(VTK_SHORT, 1);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const bool in = i >= lo[0] && i < hi[0] && j >= lo[1] && j < hi[1] && k >= lo[2] && k < hi[2];
        *static_cast<short*>(v.Image->GetScalarPointer(i, j, k)) = static_cast<short>(in ? label : 0);
      }
  v.IJKToRAS->Identity();
  for (int a = 0; a < 3; ++a) {
    v.IJKToRAS->SetElement(a, a, s[a]);
    if (origin) v.IJKToRAS->SetElement(a, 3, origin[a]);
  }
  return v;
}

TEST(LabelComparison, ShiftedBoxHasClosedFormDiceAndSurfaceDistances) {
  const int dims[3] = {30, 30, 30}, lo[3] = {10, 10, 10}, hi[3] = {20, 20, 20};
  const int shiftedLo[3] = {12, 10, 10}, shiftedHi[3] = {22, 20, 20};
  const double spacing[3] = {0.5, 1.0, 1.0};
  rp::LabelComparison result;
  std::string error;
  // Truth label 7 against label 1: matched by overlap, not by number.
  ASSERT_TRUE(rp::CompareLabels(Box(dims, lo, hi, 1, spacing), Box(dims, shiftedLo, shiftedHi, 7, spacing), {},
                                result, error))
      << error;
  ASSERT_EQ(result.Scores.size(), 1u);
  const auto& s = result.Scores[0];
  EXPECT_EQ(s.TruthLabel, 7);
  EXPECT_EQ(s.Voxels, 1000);
  EXPECT_EQ(s.OverlapVoxels, 800);
  EXPECT_DOUBLE_EQ(s.Dice, 0.8);
  // A 2-voxel shift along x (0.5 mm voxels): no boundary voxel is more than 1 mm from the other
  // boundary, and the x faces (the only ones apart) are 1 mm apart.
  EXPECT_NEAR(s.HausdorffMm, 1.0, 1e-9);
  EXPECT_GT(s.MeanSurfaceDistanceMm, 0.0);
  EXPECT_LT(s.MeanSurfaceDistanceMm, 1.0);
  EXPECT_FALSE(result.TruthResampled);
  EXPECT_TRUE(result.UnmatchedTruth.empty());
}

TEST(LabelComparison, IdenticalLabelsOnAnotherGridScoreOne) {
  // The truth is the same box on a grid that starts 5 voxels earlier: sampled onto the test grid.
  const int dims[3] = {30, 30, 30}, lo[3] = {10, 10, 10}, hi[3] = {20, 20, 20};
  const int bigDims[3] = {40, 40, 40}, bigLo[3] = {15, 15, 15}, bigHi[3] = {25, 25, 25};
  const double spacing[3] = {1.0, 1.0, 2.0}, origin[3] = {-5.0, -5.0, -10.0};
  rp::LabelComparison result;
  std::string error;
  ASSERT_TRUE(rp::CompareLabels(Box(dims, lo, hi, 3, spacing), Box(bigDims, bigLo, bigHi, 1, spacing, origin), {},
                                result, error))
      << error;
  EXPECT_TRUE(result.TruthResampled);
  EXPECT_DOUBLE_EQ(result.Scores.at(0).Dice, 1.0);
  EXPECT_DOUBLE_EQ(result.Scores.at(0).HausdorffMm, 0.0);
}

TEST(LabelComparison, DisjointLabelIsReportedNotMatched) {
  const int dims[3] = {20, 20, 20}, lo[3] = {1, 1, 1}, hi[3] = {5, 5, 5}, lo2[3] = {10, 10, 10}, hi2[3] = {15, 15, 15};
  const double spacing[3] = {1, 1, 1};
  rp::LabelComparison result;
  std::string error;
  ASSERT_TRUE(rp::CompareLabels(Box(dims, lo, hi, 1, spacing), Box(dims, lo2, hi2, 2, spacing), {}, result, error));
  EXPECT_EQ(result.Scores.at(0).TruthLabel, 0);
  EXPECT_DOUBLE_EQ(result.Scores.at(0).Dice, 0.0);
  EXPECT_EQ(result.UnmatchedTruth, std::vector<int>{2});
  const int none[3] = {0, 0, 0};
  EXPECT_FALSE(rp::CompareLabels(Box(dims, none, none, 1, spacing), Box(dims, lo2, hi2, 2, spacing), {}, result, error));
  EXPECT_NE(error.find("no labelled voxel"), std::string::npos);
}

// The Volumes logic (what `roboplan compare-labels` runs): a segmentation file and a labelmap
// file read through the loader, scored with the segment's name; a model is refused by name and
// leaves the scene as it was.
TEST(LabelComparison, TheVolumesLogicReadsAndScoresFilesWithTheSegmentsNames) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR);
  fs::create_directories(dir);
  const int dims[3] = {30, 30, 30}, lo[3] = {10, 10, 10}, hi[3] = {20, 20, 20};
  const int shiftedLo[3] = {12, 10, 10}, shiftedHi[3] = {22, 20, 20};
  const double spacing[3] = {0.5, 1.0, 1.0};
  const rp::ImageVolume test = Box(dims, lo, hi, 1, spacing), truth = Box(dims, shiftedLo, shiftedHi, 7, spacing);
  std::string error;
  vtkNew<vtkRPSegmentationNode> segmentation;
  rp::CopyToNode(test, segmentation.GetPointer());
  rp::Segment femur;
  femur.ID = "Segment_1";
  femur.Name = "femur";
  femur.LabelValue = 1;
  segmentation->SetSegment(femur);
  ASSERT_TRUE(rp::WriteSegmentationFile((dir / "test.seg.nrrd").string(), segmentation, error)) << error;
  ASSERT_TRUE(rp::WriteVolumeFile((dir / "truth.nrrd").string(), truth.Image, truth.IJKToRAS, {}, error)) << error;

  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  vtkRPNode* a = logic->LoadLabelmap((dir / "test.seg.nrrd").string(), error);
  vtkRPNode* b = a ? logic->LoadLabelmap((dir / "truth.nrrd").string(), error) : nullptr;
  ASSERT_NE(b, nullptr) << error;
  vtkRPVolumesLogic::LabelScores scores;
  ASSERT_TRUE(logic->CompareLabels(a, b, {}, scores, error)) << error;
  ASSERT_EQ(scores.Comparison.Scores.size(), 1u);
  EXPECT_DOUBLE_EQ(scores.Comparison.Scores[0].Dice, 0.8);  // as the closed form above
  EXPECT_EQ(scores.Comparison.Scores[0].TruthLabel, 7);
  EXPECT_EQ(scores.Names.at(1).Name, "femur");
  EXPECT_TRUE(scores.TruthNames.empty());  // a plain labelmap names no label

  const int nodes = scene->GetNumberOfNodes();
  EXPECT_EQ(logic->LoadLabelmap((dir / "missing.nrrd").string(), error), nullptr);
  EXPECT_NE(error.find("missing.nrrd"), std::string::npos) << error;
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
  EXPECT_FALSE(logic->CompareLabels(a, nullptr, {}, scores, error));
}

}  // namespace
