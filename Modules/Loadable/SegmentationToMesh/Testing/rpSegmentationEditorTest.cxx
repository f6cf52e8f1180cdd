// Segmentation editing on synthetic CTs with known answers: threshold presets, region growing,
// confidence connected, morphology, components, several tissues in one labelmap, leaks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <set>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpAnalyticSolids.h"
#include "rpSegmentationEditor.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

using namespace rp;
using namespace rp::test;

namespace {

// A CT of solids: each voxel's HU = background + sum of (solid value - background) x partial
// volume (fraction of 3x3x3 subsamples inside), plus Gaussian noise.
struct SyntheticCT {
  vtkSmartPointer<vtkRPScalarVolumeNode> Volume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
};

SyntheticCT MakeCT(const std::vector<std::pair<AnalyticSolid, double>>& solids, const std::array<int, 3>& dims,
                   double background, double noise, unsigned seed = 7) {
  SyntheticCT ct;
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims.data());
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        double value = background;
        for (const auto& [solid, hu] : solids) {
          int inside = 0;
          for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b)
              for (int c = -1; c <= 1; ++c) {
                const double p[3] = {i + a / 3.0, j + b / 3.0, k + c / 3.0};
                inside += solid.SDF(p) < 0;
              }
          value += (hu - background) * inside / 27.0;
        }
        *v++ = static_cast<short>(std::lround(value + (noise > 0 ? gauss(rng) : 0.0)));
      }
  ct.Volume->SetImageData(image);
  return ct;
}

SegmentTarget Target(const std::string& id, const std::string& tissue = "bone") {
  SegmentTarget t;
  t.ID = id;
  t.TissueClass = tissue;
  return t;
}

// The file names of the shared objects mapped into this process that start with `prefix`
// (case-insensitive: ITK's are libITK* and libitk*), from /proc/self/maps.
std::set<std::string> MappedLibraries(const std::string& prefix) {
  auto lower = [](std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
  };
  std::set<std::string> mapped;
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    const size_t slash = line.rfind('/');
    if (slash == std::string::npos) continue;
    const std::string file = line.substr(slash + 1);
    if (lower(file).rfind(lower(prefix), 0) == 0) mapped.insert(file);
  }
  return mapped;
}

}  // namespace

// The logic maps no ITK until an edit runs an ITK filter: ITK (9 libraries, v3p_netlib running
// code as it loads) is libRoboPlanSegmentationItk.so's, loaded by the first such edit, so `mesh
// --help`, `demo --help` and every command of a module that depends on this one start without it.
// Registered as a process of its own (no edit before it; Testing/CMakeLists.txt).
TEST(SegmentationEditorLoading, ItkIsMappedFromTheFirstEditOnly) {
  ASSERT_FALSE(MappedLibraries("libRoboPlanSegmentationToMeshLogic").empty()) << "the test links the logic";
  EXPECT_EQ(MappedLibraries("libitk"), std::set<std::string>{}) << "ITK is mapped before any edit";
  EXPECT_TRUE(MappedLibraries("libRoboPlanSegmentationItk").empty());
  // What needs no ITK does not load it.
  ASSERT_NE(FindThresholdPreset("bone"), nullptr);
  const AnalyticSolid bone = Sphere({10.2, 9.9, 10.1}, 5.0);
  SyntheticCT ct = MakeCT({{bone, 1000}}, {21, 21, 21}, 0, 0);
  vtkNew<vtkRPSegmentationNode> seg;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::InitializeFromVolume(ct.Volume, seg, error)) << error;
  EXPECT_EQ(MappedLibraries("libitk"), std::set<std::string>{});

  EditResult result;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), 500, 3000, result, error)) << error;
  const long thresholded = result.Voxels;
  EXPECT_EQ(thresholded, CountLabel(seg, 1));
  EXPECT_EQ(MappedLibraries("libRoboPlanSegmentationItk").size(), 1u);
  EXPECT_EQ(MappedLibraries("libITKCommon").size(), 1u);
  EXPECT_EQ(MappedLibraries("libitkv3p_netlib").size(), 1u);
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(seg, "bone", Morphology::Dilate, 1.0, result, error)) << error;
  EXPECT_GT(result.Voxels, thresholded);
}

TEST(SegmentationEditor, ThresholdPresetMatchesTheTruthAndCarriesTheTissueClass) {
  const AnalyticSolid bone = Sphere({20.3, 19.6, 20.2}, 10.0);
  SyntheticCT ct = MakeCT({{bone, 1000}}, {41, 41, 41}, 0, 40);
  auto truth = Rasterize(bone, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  vtkNew<vtkRPSegmentationNode> seg;
  const ThresholdPreset* preset = FindThresholdPreset("bone");
  ASSERT_NE(preset, nullptr);
  EXPECT_EQ(preset->Lower, 226);
  SegmentTarget target = Target("bone", preset->TissueClass);
  EditResult result;
  std::string error;
  // Half-way between background and bone: the partial-volume boundary is at the true surface.
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, target, 500, preset->Upper, result, error)) << error;
  const double dice = Dice(seg, seg->GetSegmentByID("bone")->LabelValue, truth, 1);
  EXPECT_GT(dice, 0.98);
  EXPECT_EQ(seg->GetSegmentByID("bone")->TissueClass, "bone");
  EXPECT_EQ(result.Voxels, CountLabel(seg, seg->GetSegmentByID("bone")->LabelValue));
}

TEST(SegmentationEditor, RegionGrowingKeepsOnlyTheSeededObject) {
  const AnalyticSolid femur = Sphere({14.2, 20.1, 20.3}, 8.0);
  const AnalyticSolid other = Sphere({33.1, 20.2, 19.9}, 5.0);
  SyntheticCT ct = MakeCT({{femur, 1000}, {other, 1000}}, {44, 40, 40}, 0, 30);
  auto truth = Rasterize(femur, {44, 40, 40}, {1, 1, 1}, {0, 0, 0});
  vtkNew<vtkRPSegmentationNode> seg;
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::RegionGrow(ct.Volume, seg, Target("femur"), {{{14, 20, 20}}}, 500, 3000, result,
                                             error))
      << error;
  EXPECT_GT(Dice(seg, 1, truth, 1), 0.97);
  // A seed outside the range is refused by name.
  EXPECT_FALSE(SegmentationEditor::RegionGrow(ct.Volume, seg, Target("femur"), {{{1, 1, 1}}}, 500, 3000, result, error));
  EXPECT_NE(error.find("outside the range"), std::string::npos) << error;
  EXPECT_FALSE(SegmentationEditor::RegionGrow(ct.Volume, seg, Target("femur"), {{{100, 1, 1}}}, 500, 3000, result, error));
  EXPECT_NE(error.find("outside the volume"), std::string::npos) << error;
  // The failed calls left the segment as it was.
  EXPECT_GT(Dice(seg, 1, truth, 1), 0.97);

  // Confidence connected from the same seed finds the same object.
  vtkNew<vtkRPSegmentationNode> seg2;
  ASSERT_TRUE(SegmentationEditor::ConfidenceConnected(ct.Volume, seg2, Target("femur"), {{{14, 20, 20}}}, 3.0, 2, 2,
                                                      result, error))
      << error;
  EXPECT_GT(Dice(seg2, 1, truth, 1), 0.9);
}

TEST(SegmentationEditor, ComponentsKeepLargestAtSeedAndSplit) {
  const AnalyticSolid big = Sphere({14.2, 20.1, 20.3}, 8.0);
  const AnalyticSolid small = Sphere({33.1, 20.2, 19.9}, 5.0);
  SyntheticCT ct = MakeCT({{big, 1000}, {small, 1000}}, {44, 40, 40}, 0, 0);
  auto truthBig = Rasterize(big, {44, 40, 40}, {1, 1, 1}, {0, 0, 0});
  auto truthSmall = Rasterize(small, {44, 40, 40}, {1, 1, 1}, {0, 0, 0});
  vtkNew<vtkRPSegmentationNode> seg;
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), 500, 3000, result, error));
  ASSERT_TRUE(SegmentationEditor::SplitComponents(seg, "bone", 5, 1, result, error)) << error;
  EXPECT_EQ(result.Components, 2);
  ASSERT_EQ(result.SegmentIDs.size(), 2u);
  EXPECT_EQ(result.SegmentIDs[0], "bone");
  EXPECT_EQ(result.SegmentIDs[1], "bone_2");
  EXPECT_GT(Dice(seg, seg->GetSegmentByID("bone")->LabelValue, truthBig, 1), 0.97);
  EXPECT_GT(Dice(seg, seg->GetSegmentByID("bone_2")->LabelValue, truthSmall, 1), 0.95);
  EXPECT_EQ(seg->GetSegmentByID("bone_2")->TissueClass, "bone");

  vtkNew<vtkRPSegmentationNode> seg2;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg2, Target("bone"), 500, 3000, result, error));
  ASSERT_TRUE(SegmentationEditor::KeepComponentAtSeed(seg2, "bone", {33, 20, 20}, result, error)) << error;
  EXPECT_GT(Dice(seg2, 1, truthSmall, 1), 0.95);
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg2, Target("bone"), 500, 3000, result, error));
  ASSERT_TRUE(SegmentationEditor::KeepLargestComponent(seg2, "bone", result, error)) << error;
  EXPECT_GT(Dice(seg2, 1, truthBig, 1), 0.97);
  EXPECT_FALSE(SegmentationEditor::KeepComponentAtSeed(seg2, "bone", {2, 2, 2}, result, error));
  EXPECT_NE(error.find("not inside"), std::string::npos);
}

TEST(SegmentationEditor, MorphologyClosesFillsAndOpensWithKnownVoxelCounts) {
  // A hollow ball (shell 10 > r > 6) fills to the solid ball; a 1-voxel gap closes; opening
  // removes a thin spur.
  const AnalyticSolid outer = Sphere({20.2, 20.1, 19.8}, 10.0), inner = Sphere({20.2, 20.1, 19.8}, 6.0);
  auto solid = Rasterize(outer, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  auto hole = Rasterize(inner, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  auto* v = static_cast<unsigned char*>(solid->GetImageData()->GetScalarPointer());
  const auto* h = static_cast<unsigned char*>(hole->GetImageData()->GetScalarPointer());
  const long solidCount = CountLabel(solid, 1);
  for (vtkIdType n = 0; n < solid->GetImageData()->GetNumberOfPoints(); ++n)
    if (h[n]) v[n] = 0;
  EXPECT_LT(CountLabel(solid, 1), solidCount);
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(solid, "sphere", Morphology::FillHoles, 0, result, error)) << error;
  EXPECT_EQ(result.Voxels, solidCount);

  // Opening removes a 1-voxel spur sticking out of the ball; closing refills a 1-voxel slit.
  const long before = CountLabel(solid, 1);
  for (int i = 31; i < 39; ++i) solid->GetImageData()->SetScalarComponentFromDouble(i, 20, 20, 0, 1);
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(solid, "sphere", Morphology::Opening, 1.0, result, error)) << error;
  for (int i = 32; i < 39; ++i) EXPECT_EQ(solid->GetImageData()->GetScalarComponentAsDouble(i, 20, 20, 0), 0) << i;
  EXPECT_LT(result.Voxels, before);
  EXPECT_GT(result.Voxels, before * 0.9);
  auto slit = Rasterize(outer, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  const long full = CountLabel(slit, 1);
  for (int j = 0; j < 41; ++j)
    for (int i = 0; i < 41; ++i) slit->GetImageData()->SetScalarComponentFromDouble(i, j, 20, 0, 0);
  ASSERT_LT(CountLabel(slit, 1), full);
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(slit, "sphere", Morphology::Closing, 1.0, result, error)) << error;
  EXPECT_NEAR(static_cast<double>(result.Voxels), static_cast<double>(full), 0.02 * full);
  EXPECT_FALSE(SegmentationEditor::ApplyMorphology(slit, "nope", Morphology::Closing, 1.0, result, error));
  EXPECT_NE(error.find("no segment 'nope'"), std::string::npos);
}

TEST(SegmentationEditor, SeveralTissuesShareOneLabelmapWithoutOverwriting) {
  const AnalyticSolid body = Sphere({20.1, 20.2, 19.9}, 16.0), bone = Sphere({20.1, 20.2, 19.9}, 7.0);
  // Fat body (-100 HU) around bone (1000 HU), in air (-1000 HU).
  SyntheticCT ct = MakeCT({{body, -100}, {bone, 1100}}, {41, 41, 41}, -1000, 10);
  vtkNew<vtkRPSegmentationNode> seg;
  EditResult result;
  std::string error;
  const ThresholdPreset* bonePreset = FindThresholdPreset("bone");
  const ThresholdPreset* fatPreset = FindThresholdPreset("fat");
  ASSERT_TRUE(bonePreset && fatPreset);
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone", "bone"), bonePreset->Lower,
                                            bonePreset->Upper, result, error));
  const long boneVoxels = result.Voxels;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("fat", "fat"), fatPreset->Lower, fatPreset->Upper,
                                            result, error))
      << error;
  ASSERT_EQ(seg->GetNumberOfSegments(), 2);
  EXPECT_EQ(seg->GetSegmentByID("fat")->TissueClass, "fat");
  EXPECT_NE(seg->GetSegmentByID("fat")->LabelValue, seg->GetSegmentByID("bone")->LabelValue);
  EXPECT_EQ(CountLabel(seg, seg->GetSegmentByID("bone")->LabelValue), boneVoxels);
  auto truthBone = Rasterize(bone, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  // 226 HU between fat (-100) and bone (1100) sits at 27 % partial volume: bone grows ~0.2 voxel.
  EXPECT_GT(Dice(seg, seg->GetSegmentByID("bone")->LabelValue, truthBone, 1), 0.92);
  // Fat is the shell body - bone, less the partial-volume rims (about half a voxel at the skin,
  // where air and fat mix to values outside the fat range): 4 pi 16^2 x 0.45 ~ 1450 voxels.
  const double shell = 4.0 / 3.0 * 3.14159265 * (16 * 16 * 16 - 7 * 7 * 7);
  const double rim = 4 * 3.14159265 * 16 * 16 * 0.45;
  EXPECT_NEAR(static_cast<double>(result.Voxels), shell - rim, 0.03 * shell);
}

TEST(SegmentationEditor, AThresholdThatLeaksIntoEverythingIsRefused) {
  const AnalyticSolid bone = Sphere({10.1, 10.2, 9.9}, 5.0);
  SyntheticCT ct = MakeCT({{bone, 1000}}, {21, 21, 21}, 0, 20);
  vtkNew<vtkRPSegmentationNode> seg;
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), 500, 3000, result, error));
  const long kept = result.Voxels;
  EXPECT_FALSE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), -2000, 3000, result, error));
  EXPECT_NE(error.find("leaked"), std::string::npos) << error;
  EXPECT_NE(error.find("100 %"), std::string::npos) << error;
  EXPECT_EQ(CountLabel(seg, 1), kept);  // untouched
  EXPECT_FALSE(SegmentationEditor::RegionGrow(ct.Volume, seg, Target("bone"), {{{10, 10, 10}}}, -500, 3000, result,
                                              error));
  EXPECT_NE(error.find("leaked"), std::string::npos) << error;
  // Allowed explicitly: the whole volume becomes the segment.
  SegmentTarget all = Target("bone");
  all.MaxFraction = 1.0;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, all, -2000, 3000, result, error)) << error;
  EXPECT_EQ(result.Voxels, 21 * 21 * 21);
  // Empty / reversed ranges and grid mismatches are errors.
  EXPECT_FALSE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), 10, -10, result, error));
  EXPECT_NE(error.find("empty"), std::string::npos);
  SyntheticCT other = MakeCT({{bone, 1000}}, {22, 21, 21}, 0, 0);
  EXPECT_FALSE(SegmentationEditor::Threshold(other.Volume, seg, Target("bone"), 500, 3000, result, error));
  EXPECT_NE(error.find("grid"), std::string::npos);
}

TEST(SegmentationEditor, HeavyNoiseIsCleanedByOpeningLargestComponentAndFillHoles) {
  // Noise of 300 HU on a 1000 HU ball: a threshold at 500 flips ~5 % of voxels (specks outside,
  // pinholes inside).
  const AnalyticSolid bone = Sphere({20.3, 19.6, 20.2}, 10.0);
  SyntheticCT ct = MakeCT({{bone, 1000}}, {41, 41, 41}, 0, 300);
  auto truth = Rasterize(bone, {41, 41, 41}, {1, 1, 1}, {0, 0, 0});
  vtkNew<vtkRPSegmentationNode> seg;
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::Threshold(ct.Volume, seg, Target("bone"), 500, 3000, result, error)) << error;
  const double noisyDice = Dice(seg, 1, truth, 1);
  EXPECT_LT(noisyDice, 0.95);
  ASSERT_TRUE(SegmentationEditor::KeepLargestComponent(seg, "bone", result, error)) << error;
  EXPECT_GT(result.Components, 10);
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(seg, "bone", Morphology::FillHoles, 0, result, error)) << error;
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(seg, "bone", Morphology::Opening, 1.0, result, error)) << error;
  const double cleanDice = Dice(seg, 1, truth, 1);
  EXPECT_GT(cleanDice, 0.95);
  EXPECT_GT(cleanDice, noisyDice);
}
