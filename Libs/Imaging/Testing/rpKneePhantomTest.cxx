// The knee phantom: deterministic, anatomically ordered, labels and intensities consistent
// with the analytic model, MR pose = the recorded CT-to-MR transform.
#include <gtest/gtest.h>

#include <ctime>
#include <cmath>
#include <cstring>

#include "rpKneePhantom.h"

namespace {

int LabelAtIndex(const rp::ImageVolume& v, int i, int j, int k) {
  return static_cast<const unsigned char*>(v.Image->GetScalarPointer(i, j, k))[0];
}

}  // namespace

TEST(KneePhantom, AnalyticModelHasTheAnatomy) {
  rp::KneeModel model;
  // Points whose tissue follows from the construction (joint line z = 0, +y anterior).
  const double femurMarrow[3] = {0, -2, 80}, tibiaMarrow[3] = {0, -2, -80};
  const double femurCortex[3] = {13.0, -2, 80};  // shaft radius 14, cortex 2 mm
  const double patella[3] = {0, 28, 30}, air[3] = {0, 70, 0}, skin[3] = {60.6, -4, 0};
  const double fat[3] = {57, -4, 0}, muscle[3] = {-30, -30, 100};
  const double fibula[3] = {32.5, -21, -120};
  EXPECT_EQ(model.LabelAt(femurMarrow), rp::KneeFemurTrabecular);
  EXPECT_EQ(model.LabelAt(femurCortex), rp::KneeFemurCortical);
  EXPECT_EQ(model.LabelAt(tibiaMarrow), rp::KneeTibiaTrabecular);
  EXPECT_EQ(model.LabelAt(patella), rp::KneePatellaTrabecular);
  EXPECT_EQ(model.LabelAt(fibula), rp::KneeFibulaTrabecular);
  EXPECT_EQ(model.LabelAt(air), rp::KneeBackground);
  EXPECT_EQ(model.LabelAt(skin), rp::KneeSkin);
  EXPECT_EQ(model.LabelAt(fat), rp::KneeFat);
  EXPECT_EQ(model.LabelAt(muscle), rp::KneeMuscle);
  // Exact distances on the primitives: femoral shaft is a capsule of radius 14 around x=0,y=-2.
  const double outside[3] = {20, -2, 100};
  EXPECT_NEAR(model.SignedDistance(rp::KneeStructure::Femur, outside), 6.0, 1e-9);
  EXPECT_NEAR(model.SignedDistance(rp::KneeStructure::FemurMarrow, outside), 8.0, 1e-9);
  // Every structure is present (has a surface) and its surface points sit on the surface.
  for (int s = 0; s <= static_cast<int>(rp::KneeStructure::Body); ++s) {
    const auto structure = static_cast<rp::KneeStructure>(s);
    const auto points = model.SurfacePoints(structure, 200);
    ASSERT_EQ(points.size(), 200u) << "structure " << s;
    for (const auto& p : points) ASSERT_LT(std::abs(model.SignedDistance(structure, p.data())), 0.01);
  }
  // Ligaments and cartilage are labelled somewhere (not hidden by bone).
  const rp::KneeStructure soft[] = {rp::KneeStructure::ACL, rp::KneeStructure::PCL, rp::KneeStructure::MCL,
                                    rp::KneeStructure::LCL, rp::KneeStructure::FemoralCartilage,
                                    rp::KneeStructure::TibialCartilage, rp::KneeStructure::PatellarCartilage};
  const rp::KneeLabel softLabels[] = {rp::KneeACL, rp::KneePCL, rp::KneeMCL, rp::KneeLCL,
                                      rp::KneeFemoralCartilage, rp::KneeTibialCartilage, rp::KneePatellarCartilage};
  for (int s = 0; s < 7; ++s) {
    int found = 0;
    for (const auto& p : model.SurfacePoints(soft[s], 300)) {
      // Step 0.3 mm inside along the numerical gradient.
      double g[3], q[3];
      for (int a = 0; a < 3; ++a) {
        double p1[3] = {p[0], p[1], p[2]}, p0[3] = {p[0], p[1], p[2]};
        p1[a] += 1e-4;
        p0[a] -= 1e-4;
        g[a] = (model.SignedDistance(soft[s], p1) - model.SignedDistance(soft[s], p0)) / 2e-4;
      }
      const double n = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      for (int a = 0; a < 3; ++a) q[a] = p[a] - 0.3 * g[a] / n;
      found += model.LabelAt(q) == softLabels[s];
    }
    EXPECT_GT(found, 30) << rp::KneeTissues()[softLabels[s]].Name << " is hidden";
  }
}

TEST(KneePhantom, SmallPhantomIsFastDeterministicAndConsistent) {
  rp::KneePhantomOptions options;
  rp::KneePhantom a, b;
  std::string error;
  // CPU time (both threads): the wall clock depends on what else the machine runs.
  const std::clock_t start = std::clock();
  double lastFraction = -1.0;
  bool monotonic = true;
  ASSERT_TRUE(rp::GenerateKneePhantom(options, a, error, [&](double f, const std::string&) {
    monotonic = monotonic && f >= lastFraction;
    lastFraction = f;
  })) << error;
  const double cpuSeconds = double(std::clock() - start) / CLOCKS_PER_SEC;
  EXPECT_LT(cpuSeconds, 2.0);
  EXPECT_TRUE(monotonic);
  EXPECT_DOUBLE_EQ(lastFraction, 1.0);
  ASSERT_TRUE(rp::GenerateKneePhantom(options, b, error)) << error;

  int dims[3];
  a.CT.Image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 96);
  EXPECT_EQ(dims[1], 96);
  EXPECT_EQ(dims[2], 64);
  double spacing[3];
  a.MR.GetSpacing(spacing);
  EXPECT_NEAR(spacing[2], 1.7, 1e-12);  // the seed's MR slice thickness
  const size_t ctBytes = size_t(dims[0]) * dims[1] * dims[2] * sizeof(short);
  EXPECT_EQ(std::memcmp(a.CT.Image->GetScalarPointer(), b.CT.Image->GetScalarPointer(), ctBytes), 0);
  int mrDims[3];
  a.MR.Image->GetDimensions(mrDims);
  EXPECT_EQ(std::memcmp(a.MR.Image->GetScalarPointer(), b.MR.Image->GetScalarPointer(),
                        size_t(mrDims[0]) * mrDims[1] * mrDims[2] * 2),
            0);

  // Labels agree with the analytic rule at voxel centres; CT HU match the tissue means in
  // voxels far from any boundary (mean over many voxels: noise averages out).
  double sumHU[rp::KneeLabelCount] = {}, count[rp::KneeLabelCount] = {};
  int checked = 0;
  for (int k = 0; k < dims[2]; k += 3)
    for (int j = 0; j < dims[1]; j += 2)
      for (int i = 0; i < dims[0]; i += 2) {
        const double ijk[3] = {double(i), double(j), double(k)};
        double ras[3];
        a.Labels.IndexToRAS(ijk, ras);
        const int label = LabelAtIndex(a.Labels, i, j, k);
        ASSERT_EQ(label, a.Model->LabelAt(ras));
        ++checked;
        // Interior: the same label 3 mm around in all axis directions.
        bool interior = true;
        for (int d = 0; d < 6 && interior; ++d) {
          double q[3] = {ras[0], ras[1], ras[2]};
          q[d / 2] += (d % 2 ? 3.0 : -3.0);
          interior = a.Model->LabelAt(q) == label;
        }
        if (interior) {
          sumHU[label] += *static_cast<short*>(a.CT.Image->GetScalarPointer(i, j, k));
          count[label] += 1;
        }
      }
  EXPECT_GT(checked, 10000);
  for (int label : {rp::KneeFat, rp::KneeMuscle, rp::KneeFemurTrabecular, rp::KneeTibiaTrabecular}) {
    ASSERT_GT(count[label], 20) << label;
    EXPECT_NEAR(sumHU[label] / count[label], rp::KneeTissues()[label].CTHounsfield, 6.0) << label;
  }
  EXPECT_DOUBLE_EQ(sumHU[rp::KneeBackground] / count[rp::KneeBackground], -1000.0);

  // The MR shows the knee moved by CTToMR: the MR voxel at CTToMR(femur marrow point) is bright
  // marrow, at CTToMR(cortex-free muscle point) muscle-like, and the CT point itself is not.
  auto mrValueAtAnatomy = [&](const double anatomy[3]) {
    double p[4] = {anatomy[0], anatomy[1], anatomy[2], 1.0};
    a.CTToMR->MultiplyPoint(p, p);
    vtkNew<vtkMatrix4x4> rasToIJK;
    vtkMatrix4x4::Invert(a.MR.IJKToRAS, rasToIJK);
    rasToIJK->MultiplyPoint(p, p);
    return double(*static_cast<unsigned short*>(a.MR.Image->GetScalarPointer(
        int(std::lround(p[0])), int(std::lround(p[1])), int(std::lround(p[2])))));
  };
  const double marrow[3] = {0, -2, 60}, muscle[3] = {-30, -25, 40};
  EXPECT_NEAR(mrValueAtAnatomy(marrow), 720 * 0.93, 70);
  EXPECT_NEAR(mrValueAtAnatomy(muscle), 350 * 0.95, 60);
}

TEST(KneePhantom, BadOptionsAreRefused) {
  rp::KneePhantomOptions options;
  options.CTDimensions = {10, 10, 10};
  options.CTSpacing = {1, 0, 1};
  rp::KneePhantom phantom;
  std::string error;
  EXPECT_FALSE(rp::GenerateKneePhantom(options, phantom, error));
  EXPECT_NE(error.find("spacing"), std::string::npos);
}
