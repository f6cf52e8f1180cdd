// The plan's figures on the real knee CT (../shared/data/knee-ct-vhf: the Visible Human Female's
// knee, 1 mm, with tibia/fibula/patella labels) against an independent VTK computation: the HU
// profile against vtkProbeFilter, the length in bone against the labels probed every 0.02 mm, the
// clearance from the fibula against vtkImplicitPolyDataDistance along the axis, and the cut
// volumes against vtkClipClosedSurface + vtkMassProperties.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <vtkClipClosedSurface.h>
#include <vtkFloatArray.h>
#include <vtkImageCast.h>
#include <vtkImageData.h>
#include <vtkImplicitPolyDataDistance.h>
#include <vtkMassProperties.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProbeFilter.h>

#include "rpDataLoader.h"
#include "rpImagingReaders.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSegmentationIO.h"
#include "rpSharedData.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

namespace {

struct Knee {
  vtkNew<vtkRPScene> Scene;
  vtkNew<vtkRPPlanningLogic> Logic;
  vtkRPScalarVolumeNode* CT = nullptr;
  vtkRPSegmentationNode* Labels = nullptr;
};

// CT (the DICOM series), labels (1 tibia, 2 fibula, 3 patella), the fibula protected by 2 mm,
// the tibia the bone.
void LoadKnee(Knee& k) {
  rp::RegisterImagingReaders();  // DICOM, as the Planning module's Setup registers it
  const rp::LoadResult ct = rp::LoadPath(k.Scene, rptest::SharedDataPath("knee-ct-vhf/dicom"));
  ASSERT_TRUE(ct.Ok) << ct.Error;
  k.CT = vtkRPScalarVolumeNode::SafeDownCast(ct.Nodes.front());
  ASSERT_NE(k.CT, nullptr);
  vtkNew<vtkRPSegmentationNode> labels;
  std::string error;
  ASSERT_TRUE(rp::ReadSegmentationOrLabelmap(rptest::SharedDataPath("knee-ct-vhf/labels.nrrd"), labels, error)) << error;
  rp::Segment fibula = *labels->FindSegment("2");
  fibula.Name = "Fibula";
  fibula.Protection = {true, 2.0};
  labels->SetSegment(fibula);
  k.Labels = vtkRPSegmentationNode::SafeDownCast(k.Scene->AddNode(labels));
  k.Logic->SetScene(k.Scene);
  ASSERT_TRUE(k.Logic->SetPatientData(k.CT, k.Labels, error, {"1"})) << error;
}

// Points along the axis every `step`, in RAS.
std::vector<rp::Vec3> Along(const rp::Vec3& a, const rp::Vec3& b, double step) {
  const int n = static_cast<int>(std::ceil(rp::Norm(b - a) / step));
  std::vector<rp::Vec3> points;
  for (int i = 0; i <= n; ++i) points.push_back(a + (b - a) * (static_cast<double>(i) / n));
  return points;
}

// vtkProbeFilter of an image node at RAS points (mapped to its IJK: the image has origin 0 and
// spacing 1), on the voxels as doubles (the probe writes the source's type: integer CT numbers
// would come back rounded).
std::vector<double> Probe(vtkRPImageNode* node, const std::vector<rp::Vec3>& ras) {
  vtkNew<vtkMatrix4x4> rasToIJK;
  node->GetRASToIJKMatrix(rasToIJK);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();  // float positions would move the samples by 1e-5 voxel
  for (const rp::Vec3& p : ras) {
    const double in[4] = {p.x, p.y, p.z, 1};
    double out[4];
    rasToIJK->MultiplyPoint(in, out);
    points->InsertNextPoint(out);
  }
  vtkNew<vtkPolyData> input;
  input->SetPoints(points);
  vtkNew<vtkImageCast> cast;
  cast->SetInputData(node->GetImageData());
  cast->SetOutputScalarTypeToDouble();
  vtkNew<vtkProbeFilter> probe;
  probe->SetInputData(input);
  probe->SetSourceConnection(cast->GetOutputPort());
  probe->Update();
  vtkDataArray* values = probe->GetOutput()->GetPointData()->GetScalars();
  std::vector<double> out;
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i) out.push_back(values->GetTuple1(i));
  return out;
}

}  // namespace

TEST(PlanRealKnee, ATibialTunnelsFiguresMatchVTKsOwnComputation) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  Knee k;
  LoadKnee(k);
  if (HasFatalFailure()) return;
  // A tunnel from the anteromedial face of the tibia up to the middle of the plateau.
  vtkNew<vtkRPTrajectoryNode> tunnel;
  tunnel->SetName("Tibial tunnel");
  const double entry[3] = {-206, -247, 440}, target[3] = {-183, -272, 488};
  tunnel->SetEntryAndTarget(entry, target);
  tunnel->SetToolDiameterMm(4.0);
  k.Scene->AddNode(tunnel);
  rp::TrajectoryFigures f;
  std::string error;
  ASSERT_TRUE(k.Logic->ComputeFigures(tunnel, f, error)) << error;
  const rp::Vec3 a{entry[0], entry[1], entry[2]}, b{target[0], target[1], target[2]};
  const rp::Vec3 u = rp::Normalized(b - a);

  // HU profile on the axis: vtkProbeFilter's trilinear interpolation at the same points.
  std::vector<rp::Vec3> depths;
  for (const auto& s : f.Profile) depths.push_back(a + u * s.DepthMm);
  const std::vector<double> probed = Probe(k.CT, depths);
  ASSERT_EQ(probed.size(), f.Profile.size());
  double worstHU = 0;
  for (size_t i = 0; i < probed.size(); ++i) worstHU = std::max(worstHU, std::fabs(probed[i] - f.Profile[i].HU));
  EXPECT_LT(worstHU, 1e-6) << "HU difference from vtkProbeFilter";

  // Length in the tibia: the labels probed every 0.02 mm (tibia = 1, by the trilinear mask's 0.5).
  vtkNew<vtkImageData> tibiaMask;
  tibiaMask->DeepCopy(k.Labels->GetImageData());
  vtkDataArray* labels = tibiaMask->GetPointData()->GetScalars();
  vtkNew<vtkFloatArray> mask;
  mask->SetNumberOfTuples(labels->GetNumberOfTuples());
  for (vtkIdType i = 0; i < labels->GetNumberOfTuples(); ++i) mask->SetValue(i, labels->GetTuple1(i) == 1 ? 1.f : 0.f);
  tibiaMask->GetPointData()->SetScalars(mask);
  vtkNew<vtkRPSegmentationNode> maskNode;
  maskNode->SetImageData(tibiaMask);
  maskNode->SetIJKToRASMatrix(k.Labels->GetIJKToRASMatrix());
  const double step = 0.02;
  const std::vector<double> inTibia = Probe(maskNode, Along(a, b, step));
  double length = 0;
  for (size_t i = 0; i + 1 < inTibia.size(); ++i) length += (0.5 * (inTibia[i] + inTibia[i + 1]) >= 0.5) * rp::Norm(b - a) / (inTibia.size() - 1);
  EXPECT_GT(f.LengthInBoneMm, 20);
  EXPECT_NEAR(f.LengthInBoneMm, length, 0.1) << "length in the tibia against the labels probed every 0.02 mm";

  // Clearance from the fibula: vtkImplicitPolyDataDistance along the axis, less the tool's radius.
  ASSERT_EQ(f.Clearances.size(), 1u);
  const auto structures = k.Logic->GetStructuresAtRisk();
  const auto surface = k.Logic->GetStructureSurface(structures[0], error);
  ASSERT_NE(surface, nullptr) << error;
  vtkNew<vtkImplicitPolyDataDistance> distance;
  distance->SetInput(rp::TriangleMeshToPolyData(*surface));
  double closest = HUGE_VAL, closestDepth = 0;
  const std::vector<rp::Vec3> samples = Along(a, b, 0.01);
  for (size_t i = 0; i < samples.size(); ++i) {
    const double d = std::fabs(distance->EvaluateFunction(samples[i].x, samples[i].y, samples[i].z));
    if (d < closest) closest = d, closestDepth = rp::Norm(samples[i] - a);
  }
  EXPECT_NEAR(f.Clearances[0].ClearanceMm, closest - 2.0, 0.005) << "clearance from the fibula";
  EXPECT_NEAR(f.Clearances[0].DepthMm, closestDepth, 0.5);
  std::cout << "real knee tunnel: length " << f.LengthMm << " mm, in tibia " << f.LengthInBoneMm << " mm (VTK " << length
            << "), clearance from the fibula " << f.Clearances[0].ClearanceMm << " mm (VTK " << closest - 2.0 << ") at "
            << f.Clearances[0].DepthMm << " mm, HU max difference " << worstHU << ", breach "
            << (f.Breach.Found ? std::to_string(f.Breach.BreachMm) + " mm at depth " + std::to_string(f.Breach.DepthMm) + " mm": std::string("none")) << "; bone";
  for (const auto& b : f.Bone) std::cout << " [" << b.FromMm << ", " << b.ToMm << "]";
  std::cout << "\n";
}

TEST(PlanRealKnee, ACutThroughTheTibiaMatchesVTKsClippedVolumes) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  Knee k;
  LoadKnee(k);
  if (HasFatalFailure()) return;
  vtkNew<vtkRPCutPlaneNode> plane;
  const double origin[3] = {-180, -270, 470}, normal[3] = {0.1, -0.2, 1};
  plane->SetOrigin(origin);
  plane->SetNormal(normal);
  k.Scene->AddNode(plane);
  std::vector<vtkRPPlanningLogic::BoneCut> cuts;
  std::string error;
  ASSERT_TRUE(k.Logic->ComputeCut(plane, cuts, error)) << error;
  ASSERT_EQ(cuts.size(), 1u);  // the tibia, the one bone named
  // VTK: the same surface clipped by the plane, closed, and its volume.
  const rp::Segment* tibia = k.Labels->FindSegment("1");
  rp::TriangleMesh mesh;
  {
    vtkRPPlanningLogic::StructureAtRisk s{k.Labels, tibia->ID, "tibia", 0};
    const auto surface = k.Logic->GetStructureSurface(s, error);
    ASSERT_NE(surface, nullptr) << error;
    mesh = *surface;
  }
  double n[3];
  plane->GetNormal(n);
  vtkNew<vtkPlane> vtkPlaneObject;
  vtkPlaneObject->SetOrigin(const_cast<double*>(origin));
  vtkPlaneObject->SetNormal(n);  // vtkClipClosedSurface keeps the normal's side
  vtkNew<vtkPlaneCollection> planes;
  planes->AddItem(vtkPlaneObject);
  vtkNew<vtkClipClosedSurface> clip;
  clip->SetInputData(rp::TriangleMeshToPolyData(mesh));
  clip->SetClippingPlanes(planes);
  clip->Update();
  vtkNew<vtkMassProperties> mass;
  mass->SetInputConnection(clip->GetOutputPort());
  mass->Update();
  const rp::CutFigures& c = cuts[0].Figures;
  EXPECT_GT(c.PositiveVolumeMm3, 1000);
  EXPECT_NEAR(c.PositiveVolumeMm3, mass->GetVolume(), 1e-3 * mass->GetVolume());
  std::cout << "real knee cut: tibia " << c.VolumeMm3 << " mm3, above " << c.PositiveVolumeMm3 << " (VTK "
            << mass->GetVolume() << "), below " << c.NegativeVolumeMm3 << ", cut " << c.CutAreaMm2 << " mm2\n";
}
