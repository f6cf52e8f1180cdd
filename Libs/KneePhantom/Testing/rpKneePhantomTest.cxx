// The knee phantom. Analytic anatomy: deterministic, labels and intensities consistent with
// closed-form distances. Real anatomy: the shipped surfaces are closed, in the anatomy frame and
// within 0.05 mm of the source surfaces (../shared/data); the labelmap agrees with VTK's own
// voxelization of the same surfaces (vtkPolyDataToImageStencil); tissues have their CT values;
// the MR sees the knee moved by the recorded CT-to-MR pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>

#include <vtkImageData.h>
#include <vtkImageStencilData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataToImageStencil.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkXMLPolyDataReader.h>

#include "rpKneePhantom.h"
#include "rpSharedData.h"

namespace fs = std::filesystem;

namespace {

int LabelAtIndex(const rp::ImageVolume& v, int i, int j, int k) {
  return static_cast<const unsigned char*>(v.Image->GetScalarPointer(i, j, k))[0];
}

std::shared_ptr<const rp::KneeModel> RealKnee() {
  std::string error;
  auto model = rp::LoadKneeSurfaceModel(error);
  EXPECT_TRUE(model) << error;
  return model;
}

const rp::KneePhantom& RealPhantom() {
  static rp::KneePhantom phantom;
  static bool made = [] {
    rp::KneePhantomOptions options;  // real anatomy, small
    std::string error;
    const bool ok = rp::GenerateKneePhantom(options, phantom, error);
    EXPECT_TRUE(ok) << error;
    return ok;
  }();
  (void)made;
  return phantom;
}

// MR value at an anatomical point (CT RAS) of a phantom.
double MRAtAnatomy(const rp::KneePhantom& phantom, const double anatomy[3]) {
  double p[4] = {anatomy[0], anatomy[1], anatomy[2], 1.0};
  phantom.CTToMR->MultiplyPoint(p, p);
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(phantom.MR.IJKToRAS, rasToIJK);
  rasToIJK->MultiplyPoint(p, p);
  return double(*static_cast<unsigned short*>(phantom.MR.Image->GetScalarPointer(
      int(std::lround(p[0])), int(std::lround(p[1])), int(std::lround(p[2])))));
}

}  // namespace

TEST(KneePhantom, AnalyticModelHasTheAnatomy) {
  rp::KneeAnalyticModel model;
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
  // Every structure is present (has a surface), its surface points sit on it and in its bounds.
  for (int s = 0; s < rp::KneeStructureCount; ++s) {
    const auto structure = static_cast<rp::KneeStructure>(s);
    const auto points = model.SurfacePoints(structure, 200);
    ASSERT_EQ(points.size(), 200u) << rp::KneeStructureName(structure);
    double b[6];
    model.Bounds(structure, b);
    for (const auto& p : points) {
      ASSERT_LT(std::abs(model.SignedDistance(structure, p.data())), 0.01);
      for (int a = 0; a < 3; ++a) ASSERT_TRUE(p[a] >= b[2 * a] && p[a] <= b[2 * a + 1]) << rp::KneeStructureName(structure);
    }
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

TEST(KneePhantom, AnalyticPhantomIsFastDeterministicAndConsistent) {
  rp::KneePhantomOptions options;
  options.Anatomy = rp::KneeAnatomy::Analytic;
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
  EXPECT_LT(cpuSeconds, 3.0);
  EXPECT_TRUE(monotonic);
  EXPECT_DOUBLE_EQ(lastFraction, 1.0);
  ASSERT_TRUE(rp::GenerateKneePhantom(options, b, error)) << error;

  int dims[3];
  a.CT.Image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 110);
  EXPECT_EQ(dims[1], 110);
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

  // The MR shows the knee moved by CTToMR: bright marrow and muscle-like values where CTToMR
  // puts those anatomical points.
  const double marrow[3] = {0, -2, 60}, muscle[3] = {-30, -25, 40};
  EXPECT_NEAR(MRAtAnatomy(a, marrow), 720 * 0.93, 70);
  EXPECT_NEAR(MRAtAnatomy(a, muscle), 350 * 0.95, 60);
}

TEST(KneePhantom, RealKneeSurfacesAreClosedAndInTheAnatomyFrame) {
  const auto model = RealKnee();
  ASSERT_TRUE(model);
  EXPECT_NE(model->Description().find("Visible Human"), std::string::npos);
  // Every mesh structure has a closed surface whose points have distance 0.
  for (const rp::KneeStructure s :
       {rp::KneeStructure::Femur, rp::KneeStructure::Tibia, rp::KneeStructure::Fibula, rp::KneeStructure::Patella,
        rp::KneeStructure::FemoralCartilage, rp::KneeStructure::TibialCartilage, rp::KneeStructure::PatellarCartilage,
        rp::KneeStructure::ACL, rp::KneeStructure::PCL, rp::KneeStructure::MCL, rp::KneeStructure::LCL}) {
    ASSERT_TRUE(model->Surface(s)) << rp::KneeStructureName(s);
    const auto points = model->SurfacePoints(s, 300);
    ASSERT_EQ(points.size(), 300u) << rp::KneeStructureName(s);
    for (const auto& p : points) ASSERT_LT(std::abs(model->SignedDistance(s, p.data())), 1e-6);
  }
  // The joint line is z = 0: the femur ends just above it, the tibia just below.
  double femur[6], tibia[6];
  model->Bounds(rp::KneeStructure::Femur, femur);
  model->Bounds(rp::KneeStructure::Tibia, tibia);
  EXPECT_NEAR(femur[4], -tibia[5], 1.0);
  EXPECT_LT(std::abs(femur[4]), 3.0);
  // The joint spaces of the source (README of knee-vhf-surfaces): femur–tibia ≥ 3.67 mm,
  // femur–patella ≥ 2.38 mm (decimation moved the surfaces by < 0.05 mm).
  auto closest = [&](rp::KneeStructure from, rp::KneeStructure to) {
    double best = 1e9;
    for (const auto& p : model->SurfacePoints(from, 20000)) best = std::min(best, model->SignedDistance(to, p.data()));
    return best;
  };
  EXPECT_GT(closest(rp::KneeStructure::Femur, rp::KneeStructure::Tibia), 3.5);
  EXPECT_GT(closest(rp::KneeStructure::Patella, rp::KneeStructure::Femur), 2.2);
  // The generated soft tissues hold the bones: every bone point inside the body by ≥ 5 mm and
  // the cortex thin at the joint, thick in the shafts.
  const double fov[6] = {-1e9, 1e9, -1e9, 1e9, -150, 150};
  for (const auto& bone : rp::KneeBones())
    for (const auto& p : model->SurfacePoints(bone.Surface, 2000, fov))
      ASSERT_LT(model->SignedDistance(rp::KneeStructure::Body, p.data()), -5.0) << bone.Name;
  const double joint[3] = {0, 0, -5}, shaft[3] = {0, 0, -140};
  EXPECT_LT(model->CorticalThickness(rp::KneeStructure::Tibia, joint), 1.5);
  EXPECT_GT(model->CorticalThickness(rp::KneeStructure::Tibia, shaft), 3.5);
}

TEST(KneePhantom, ShippedAnatomyIsWithinFiveHundredthsOfAMillimetreOfTheSource) {
  RP_REQUIRE_SHARED_DATA("knee-vhf-surfaces/tibia.vtp");
  const fs::path source = fs::path(rptest::SharedDataPath("knee-vhf-surfaces"));
  const auto model = RealKnee();
  ASSERT_TRUE(model);
  // The frame change the shipped files were made with.
  std::ifstream frame(std::string(ROBOPLAN_RESOURCES_DIR) + "/Anatomy/KneeVHF/knee-vhf-surfaces_to_this_frame_4x4.txt");
  double m[16];
  for (double& v : m) ASSERT_TRUE(frame >> v);
  vtkNew<vtkTransform> toAnatomy;
  toAnatomy->SetMatrix(m);
  const struct {
    const char* File;
    rp::KneeStructure Structure;
  } parts[] = {{"femur.vtp", rp::KneeStructure::Femur},     {"tibia.vtp", rp::KneeStructure::Tibia},
               {"fibula.vtp", rp::KneeStructure::Fibula},   {"patella.vtp", rp::KneeStructure::Patella},
               {"ligament_acl.vtp", rp::KneeStructure::ACL}, {"cartilage_femur.vtp", rp::KneeStructure::FemoralCartilage}};
  for (const auto& part : parts) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((source / part.File).string().c_str());
    vtkNew<vtkTransformPolyDataFilter> moved;
    moved->SetInputConnection(reader->GetOutputPort());
    moved->SetTransform(toAnatomy);
    moved->Update();
    vtkPolyData* original = moved->GetOutput();
    ASSERT_GT(original->GetNumberOfPoints(), 1000) << part.File;
    double worst = 0;
    for (vtkIdType i = 0; i < original->GetNumberOfPoints(); ++i) {
      const double* p = original->GetPoint(i);
      if (std::abs(p[2]) > 165) continue;  // beyond the crop
      worst = std::max(worst, std::abs(model->SignedDistance(part.Structure, p)));
    }
    EXPECT_LT(worst, 0.051) << part.File;
  }
}

TEST(KneePhantom, RealPhantomLabelsAgreeWithVTKsVoxelizationOfTheSurfaces) {
  const rp::KneePhantom& phantom = RealPhantom();
  ASSERT_FALSE(phantom.Labels.Empty());
  int dims[3];
  phantom.Labels.Image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 110);
  EXPECT_EQ(dims[2], 64);
  // The labelmap is the rule at voxel centres (same rule as LabelAt).
  int checked = 0, mismatched = 0;
  for (int k = 0; k < dims[2]; k += 5)
    for (int j = 0; j < dims[1]; j += 3)
      for (int i = 0; i < dims[0]; i += 3) {
        const double ijk[3] = {double(i), double(j), double(k)};
        double ras[3];
        phantom.Labels.IndexToRAS(ijk, ras);
        ++checked;
        mismatched += LabelAtIndex(phantom.Labels, i, j, k) != phantom.Model->LabelAt(ras);
      }
  EXPECT_GT(checked, 10000);
  EXPECT_EQ(mismatched, 0);
  // Each bone (cortical + trabecular + the cartilage painted over it, which the surface holds
  // where they overlap) against vtkPolyDataToImageStencil on the same grid: Dice ≥ 0.98.
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(phantom.Labels.IJKToRAS, rasToIJK);
  vtkNew<vtkTransform> toIJK;
  toIJK->SetMatrix(rasToIJK);
  const auto* labels = static_cast<const unsigned char*>(phantom.Labels.Image->GetScalarPointer());
  for (const auto& bone : rp::KneeBones()) {
    vtkNew<vtkTransformPolyDataFilter> surface;
    surface->SetInputData(phantom.Model->Surface(bone.Surface));
    surface->SetTransform(toIJK);
    vtkNew<vtkPolyDataToImageStencil> stencil;
    stencil->SetInputConnection(surface->GetOutputPort());
    stencil->SetOutputOrigin(0, 0, 0);
    stencil->SetOutputSpacing(1, 1, 1);
    stencil->SetOutputWholeExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1);
    stencil->Update();
    vtkImageStencilData* inside = stencil->GetOutput();
    long both = 0, vtkCount = 0, ours = 0;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const unsigned char l = labels[(size_t(k) * dims[1] + j) * dims[0] + i];
          const bool a = l == bone.Cortical || l == bone.Trabecular;
          const bool b = inside->IsInside(i, j, k) != 0;
          both += a && b;
          ours += a;
          vtkCount += b;
        }
    ASSERT_GT(vtkCount, 100) << bone.Name;
    EXPECT_GT(2.0 * both / double(ours + vtkCount), 0.98) << bone.Name << ": ours " << ours << ", VTK " << vtkCount;
  }
}

TEST(KneePhantom, RealPhantomHasTissueValuesAndTheMRPose) {
  const rp::KneePhantom& phantom = RealPhantom();
  ASSERT_FALSE(phantom.CT.Empty());
  ASSERT_FALSE(phantom.MR.Empty());
  int dims[3];
  phantom.CT.Image->GetDimensions(dims);
  // Mean HU of voxels deep inside fat and muscle (the same label two voxels around); the cortex
  // of the shafts is dense.
  double sum[rp::KneeLabelCount] = {}, count[rp::KneeLabelCount] = {};
  short brightest = -1024;
  for (int k = 2; k < dims[2] - 2; ++k)
    for (int j = 2; j < dims[1] - 2; ++j)
      for (int i = 2; i < dims[0] - 2; ++i) {
        const int label = LabelAtIndex(phantom.Labels, i, j, k);
        const short hu = *static_cast<short*>(phantom.CT.Image->GetScalarPointer(i, j, k));
        if (label == rp::KneeFemurCortical) brightest = std::max(brightest, hu);
        bool interior = true;
        for (int d = 0; d < 6 && interior; ++d) {
          int q[3] = {i, j, k};
          q[d / 2] += (d % 2 ? 2 : -2);
          interior = LabelAtIndex(phantom.Labels, q[0], q[1], q[2]) == label;
        }
        if (interior) sum[label] += hu, count[label] += 1;
      }
  for (int label : {rp::KneeFat, rp::KneeMuscle}) {
    ASSERT_GT(count[label], 50) << label;
    EXPECT_NEAR(sum[label] / count[label], rp::KneeTissues()[label].CTHounsfield, 8.0) << label;
  }
  EXPECT_GT(brightest, 1000);  // the femoral shaft's cortex is thicker than a voxel
  // Trabecular bone: textured, densest under the joint.
  ASSERT_GT(count[rp::KneeTibiaTrabecular], 50);
  const double trabecular = sum[rp::KneeTibiaTrabecular] / count[rp::KneeTibiaTrabecular];
  EXPECT_GT(trabecular, 120);
  EXPECT_LT(trabecular, 320);
  // The MR: bright fatty marrow where CTToMR puts the middle of the tibia 30 mm below the joint
  // (the mean of its surface points at that height).
  double deep[3] = {0, 0, -30}, sx = 0, sy = 0;
  int n = 0;
  for (const auto& p : phantom.Model->SurfacePoints(rp::KneeStructure::Tibia, 20000))
    if (std::abs(p[2] + 30) < 2) sx += p[0], sy += p[1], ++n;
  ASSERT_GT(n, 20);
  deep[0] = sx / n, deep[1] = sy / n;
  ASSERT_EQ(phantom.Model->LabelAt(deep), rp::KneeTibiaTrabecular);
  EXPECT_GT(MRAtAnatomy(phantom, deep), 500);
}

TEST(KneePhantom, BadOptionsAndMissingAnatomyAreRefused) {
  rp::KneePhantomOptions options;
  options.CTDimensions = {10, 10, 10};
  options.CTSpacing = {1, 0, 1};
  rp::KneePhantom phantom;
  std::string error;
  EXPECT_FALSE(rp::GenerateKneePhantom(options, phantom, error));
  EXPECT_NE(error.find("spacing"), std::string::npos);
  // Resources without the anatomy: the error names the missing file.
  const fs::path empty = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "no-resources";
  fs::create_directories(empty);
  const char* previous = std::getenv("ROBOPLAN_RESOURCES_DIR");
  const std::string keep = previous ? previous : "";
  setenv("ROBOPLAN_RESOURCES_DIR", empty.string().c_str(), 1);
  error.clear();
  rp::KneePhantomOptions real;
  EXPECT_FALSE(rp::GenerateKneePhantom(real, phantom, error));
  EXPECT_NE(error.find("femur.vtp"), std::string::npos) << error;
  if (previous) setenv("ROBOPLAN_RESOURCES_DIR", keep.c_str(), 1);
  else unsetenv("ROBOPLAN_RESOURCES_DIR");
}
