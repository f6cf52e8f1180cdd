// The knee phantom (Libs/Imaging): bone from the CT by the threshold preset, Dice against the
// ground-truth labelmap, and bone surfaces against the analytic bones (mean / Hausdorff distance,
// volume, watertightness) for our pipeline and Slicer's default.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpKneePhantom.h"
#include "rpLabelmapToMesh.h"
#include "rpSegmentationEditor.h"
#include "rpSurfaceError.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPSegmentationNode.h"

using namespace rp;

namespace {

const KneeStructure Bones[] = {KneeStructure::Femur, KneeStructure::Tibia, KneeStructure::Fibula,
                               KneeStructure::Patella};

bool IsBone(int label) { return label >= KneeFemurCortical && label <= KneePatellaTrabecular; }

struct Phantom {
  KneePhantom Knee;
  vtkSmartPointer<vtkRPScalarVolumeNode> CT = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  vtkSmartPointer<vtkRPSegmentationNode> TruthBone = vtkSmartPointer<vtkRPSegmentationNode>::New();
  double Bounds[6];  // RAS voxel-centre bounds shrunk by 3 mm (structures leave the field of view)
  double MeanSpacing = 1;
};

const Phantom& GetPhantom() {
  static Phantom* phantom = [] {
    auto* p = new Phantom;
    KneePhantomOptions options;
    options.Anatomy = KneeAnatomy::Analytic;  // closed-form distances to score against
    options.GenerateMR = false;
    std::string error;
    if (!GenerateKneePhantom(options, p->Knee, error)) {
      ADD_FAILURE() << error;
      return p;
    }
    CopyToNode(p->Knee.CT, p->CT.GetPointer());
    vtkNew<vtkImageData> bone;
    bone->DeepCopy(p->Knee.Labels.Image);
    auto* v = static_cast<unsigned char*>(bone->GetScalarPointer());
    for (vtkIdType n = 0; n < bone->GetNumberOfPoints(); ++n) v[n] = IsBone(v[n]) ? 1 : 0;
    p->TruthBone->SetImageData(bone);
    p->TruthBone->SetIJKToRASMatrix(p->Knee.Labels.IJKToRAS);
    vtkRPSegmentationNode::Segment s;
    s.ID = "bone";
    s.TissueClass = "bone";
    s.LabelValue = 1;
    p->TruthBone->SetSegment(s);
    p->CT->GetRASBounds(p->Bounds);
    for (int a = 0; a < 3; ++a) p->Bounds[2 * a] += 3, p->Bounds[2 * a + 1] -= 3;
    double spacing[3];
    p->CT->GetSpacing(spacing);
    p->MeanSpacing = std::cbrt(spacing[0] * spacing[1] * spacing[2]);
    return p;
  }();
  return *phantom;
}

SignedDistanceFunction BoneSDF(const KneeModel& model) {
  return [&model](const double p[3]) {
    double d = 1e300;
    for (KneeStructure b : Bones) d = std::min(d, model.SignedDistance(b, p));
    return d;
  };
}

std::vector<std::array<double, 3>> BonePoints(const KneeModel& model, const double* bounds) {
  std::vector<std::array<double, 3>> points;
  for (KneeStructure b : Bones) {
    auto part = model.SurfacePoints(b, 3000, bounds);
    // Points of one bone inside another (none expected) are not on the union's surface.
    for (const auto& q : part) {
      const double p[3] = {q[0], q[1], q[2]};
      bool inOther = false;
      for (KneeStructure o : Bones)
        if (o != b && model.SignedDistance(o, p) < -0.05) inOther = true;
      if (!inOther) points.push_back(q);
    }
  }
  return points;
}

}  // namespace

TEST(KneePhantomMesh, BoneThresholdMatchesTheGroundTruth) {
  const Phantom& p = GetPhantom();
  ASSERT_TRUE(p.Knee.Model);
  vtkNew<vtkRPSegmentationNode> seg;
  const ThresholdPreset* bone = FindThresholdPreset("bone");
  SegmentTarget target;
  target.ID = "bone";
  target.TissueClass = bone->TissueClass;
  EditResult result;
  std::string error;
  ASSERT_TRUE(SegmentationEditor::Threshold(p.CT, seg, target, bone->Lower, bone->Upper, result, error)) << error;
  ASSERT_TRUE(SegmentationEditor::ApplyMorphology(seg, "bone", Morphology::FillHoles, 0, result, error)) << error;
  // Dice of the thresholded labelmap against the truth's bone labels.
  const auto* a = static_cast<const unsigned char*>(seg->GetImageData()->GetScalarPointer());
  const auto* t = static_cast<const unsigned char*>(p.TruthBone->GetImageData()->GetScalarPointer());
  long na = 0, nt = 0, both = 0;
  for (vtkIdType n = 0; n < seg->GetImageData()->GetNumberOfPoints(); ++n) {
    na += a[n] == 1, nt += t[n] == 1, both += a[n] == 1 && t[n] == 1;
  }
  const double dice = 2.0 * both / static_cast<double>(na + nt);
  std::printf("bone threshold %g HU + fill holes: Dice %.4f (%ld vs %ld voxels)\n", bone->Lower, dice, na, nt);
  EXPECT_GT(dice, 0.9);
}

TEST(KneePhantomMesh, BoneSurfaceIsAccurateWatertightAndKeepsVolume) {
  const Phantom& p = GetPhantom();
  ASSERT_TRUE(p.Knee.Model);
  const auto sdf = BoneSDF(*p.Knee.Model);
  const auto points = BonePoints(*p.Knee.Model, p.Bounds);
  ASSERT_GT(points.size(), 1000u);
  MeshOptions gaussian;
  MeshOptions slicer;
  slicer.Method = MeshMethod::SlicerDefault;
  SurfaceError errors[2];
  double volumeErrors[2] = {0, 0};
  int m = 0;
  for (const MeshOptions& options : {gaussian, slicer}) {
    vtkNew<vtkPolyData> mesh;
    MeshStats stats;
    std::string error;
    ASSERT_TRUE(LabelmapToMesh(p.TruthBone->GetImageData(), p.TruthBone->GetIJKToRASMatrix(), 1, options, mesh, stats,
                               error))
        << error;
    const SurfaceError e = CompareToSurface(mesh, sdf, points, p.Bounds);
    volumeErrors[m] = stats.VolumeErrorPercent;
    errors[m++] = e;
    std::printf("knee bone %-8s tris %ld  mean %.3f mm (%.3f voxel)  hausdorff %.3f mm  volume vs labelmap %+.2f %%  "
                "watertight %d  %.3f s\n",
                MeshMethodName(options.Method), stats.Triangles, e.MeanMm, e.MeanMm / p.MeanSpacing, e.HausdorffMm,
                stats.VolumeErrorPercent, stats.Watertight, stats.Seconds);
    EXPECT_TRUE(stats.Watertight) << MeshMethodName(options.Method);
    if (options.Method == MeshMethod::Gaussian) {
      EXPECT_LT(std::abs(stats.VolumeErrorPercent), 1.0);
      EXPECT_LT(e.MeanMm / p.MeanSpacing, 0.25);
    }
  }
  // Both are far below a quarter voxel; the blur is within 15 % of Slicer's mean error, with a
  // smaller worst case and the labelmap's volume.
  EXPECT_LE(errors[0].MeanMm, errors[1].MeanMm * 1.15);
  EXPECT_LT(errors[0].HausdorffMm, errors[1].HausdorffMm);
  EXPECT_LE(std::abs(volumeErrors[0]), std::abs(volumeErrors[1]));
}
