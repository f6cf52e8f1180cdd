// The SegmentationToMesh panel on a synthetic CT (a 1000 HU sphere in -1000 HU): the volume combo
// follows the scene, a missing seed list is a red error that changes nothing, preset "bone" +
// Apply gives exactly the sphere's voxels, Preview keeps one preview model, Create models gives a
// closed "bone" model enclosing the sphere's volume, region growing from a fiducial finds it too.
#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSpinBox>
#include <QTest>

#include <cmath>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "qRPSegmentationToMeshPanel.h"
#include "rpLabelmapToMesh.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSegmentationToMeshLogic.h"

namespace {

constexpr int kDim = 56;
constexpr double kSpacing = 0.75;             // mm
constexpr double kOrigin[3] = {-20, -21, -19};  // RAS of voxel (0,0,0)
constexpr double kCentre[3] = {0.3, -0.4, 0.2};  // RAS
constexpr double kRadius = 15.0;               // mm

bool InSphere(int i, int j, int k) {
  const double p[3] = {kOrigin[0] + kSpacing * i - kCentre[0], kOrigin[1] + kSpacing * j - kCentre[1],
                       kOrigin[2] + kSpacing * k - kCentre[2]};
  return p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= kRadius * kRadius;
}

vtkSmartPointer<vtkRPScalarVolumeNode> MakeSphereCT(long& sphereVoxels) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(kDim, kDim, kDim);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* values = static_cast<short*>(image->GetScalarPointer());
  sphereVoxels = 0;
  for (int k = 0; k < kDim; ++k)
    for (int j = 0; j < kDim; ++j)
      for (int i = 0; i < kDim; ++i) {
        const bool inside = InSphere(i, j, k);
        sphereVoxels += inside;
        values[(k * kDim + j) * kDim + i] = inside ? 1000 : -1000;
      }
  auto volume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  volume->SetName("SphereCT");
  volume->SetImageData(image);
  const double spacing[3] = {kSpacing, kSpacing, kSpacing};
  const double directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  volume->SetGeometry(spacing, kOrigin, directions);
  return volume;
}

long CountLabel(vtkRPSegmentationNode* segmentation, const std::string& id) {
  const auto* segment = segmentation->GetSegmentByID(id);
  if (!segment) return -1;
  vtkDataArray* labels = segmentation->GetImageData()->GetPointData()->GetScalars();
  long n = 0;
  for (vtkIdType v = 0; v < labels->GetNumberOfTuples(); ++v) n += labels->GetTuple1(v) == segment->LabelValue;
  return n;
}

// One application for every test of this program (Qt wants one per process).
QApplication& App() {
  static int argc = 1;
  static char name[] = "qRPSegmentationToMeshPanelTest";
  static char* argv[] = {name};
  static QApplication app(argc, argv);
  return app;
}

std::vector<vtkRPModelNode*> Models(vtkRPScene* scene) {
  std::vector<vtkRPModelNode*> models;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) models.push_back(vtkRPModelNode::SafeDownCast(node));
  return models;
}

}  // namespace

TEST(SegmentationToMeshPanel, SphereCTPresetBoneApplyPreviewCreateModels) {
  App();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPSegmentationToMeshLogic> logic;
  logic->SetScene(scene);
  qRPSegmentationToMeshPanel panel(logic);
  panel.show();
  EXPECT_EQ(panel.VolumeCombo->count(), 0);

  // The combos follow the scene.
  long sphereVoxels = 0;
  auto volume = MakeSphereCT(sphereVoxels);
  scene->AddNode(volume);
  vtkNew<vtkRPScalarVolumeNode> other;
  other->SetName("Other");
  scene->AddNode(other);
  EXPECT_EQ(panel.VolumeCombo->count(), 2);
  scene->RemoveNode(other);
  ASSERT_EQ(panel.VolumeCombo->count(), 1);
  EXPECT_EQ(panel.VolumeCombo->currentText(), "SphereCT");
  ASSERT_EQ(panel.CurrentVolume(), volume.Get());
  // Sanity of the phantom against the analytic ball (voxel count ≈ 4/3 π R³ / voxel volume).
  const double ballVolume = 4.0 / 3.0 * M_PI * kRadius * kRadius * kRadius;
  EXPECT_NEAR(sphereVoxels * kSpacing * kSpacing * kSpacing / ballVolume, 1.0, 0.02);

  // Region growing without seeds: a red error, nothing created.
  panel.MethodCombo->setCurrentIndex(qRPSegmentationToMeshPanel::RegionGrowing);
  QTest::mouseClick(panel.ApplyButton, Qt::LeftButton);
  EXPECT_TRUE(panel.HasError());
  EXPECT_TRUE(panel.StatusText().contains("seeds")) << panel.StatusText().toStdString();
  EXPECT_TRUE(panel.StatusLabel->styleSheet().contains("red"));
  EXPECT_TRUE(scene->GetNodesByClass("vtkRPSegmentationNode").empty());

  // Preset bone + Apply: exactly the sphere's voxels, tissue class bone.
  panel.MethodCombo->setCurrentIndex(qRPSegmentationToMeshPanel::PresetThreshold);
  panel.PresetCombo->setCurrentText("cortical");
  panel.PresetCombo->setCurrentText("bone");
  EXPECT_EQ(panel.SegmentNameEdit->text(), "bone");
  EXPECT_EQ(panel.TissueCombo->currentText(), "bone");
  QTest::mouseClick(panel.ApplyButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  vtkRPSegmentationNode* segmentation = panel.CurrentSegmentation();
  ASSERT_NE(segmentation, nullptr);
  ASSERT_EQ(segmentation->GetNumberOfSegments(), 1);
  EXPECT_EQ(segmentation->GetNthSegment(0).TissueClass, "bone");
  EXPECT_EQ(CountLabel(segmentation, "bone"), sphereVoxels);
  EXPECT_EQ(panel.CurrentSegmentID(), "bone");
  EXPECT_TRUE(panel.StatusText().contains(QString::number(sphereVoxels))) << panel.StatusText().toStdString();

  // Preview twice: one preview model, replaced.
  panel.HapticTrianglesSpin->setValue(5000);
  QTest::mouseClick(panel.PreviewButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  QTest::mouseClick(panel.PreviewButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  ASSERT_EQ(Models(scene).size(), 1u);
  EXPECT_EQ(Models(scene)[0]->GetName(), "bone (preview)");
  EXPECT_EQ(Models(scene)[0]->GetID(), panel.PreviewNodeID());
  EXPECT_GT(Models(scene)[0]->GetPolyData()->GetNumberOfCells(), 1000);

  // Create models: the preview goes, a display and a haptic model of tissue bone come.
  QTest::mouseClick(panel.CreateModelsButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_TRUE(panel.PreviewNodeID().empty());
  EXPECT_EQ(scene->GetFirstNodeByName("bone (preview)"), nullptr);
  auto* display = vtkRPModelNode::SafeDownCast(scene->GetFirstNodeByName("bone"));
  auto* haptic = vtkRPModelNode::SafeDownCast(scene->GetFirstNodeByName("bone (haptic)"));
  ASSERT_NE(display, nullptr);
  ASSERT_NE(haptic, nullptr);
  EXPECT_EQ(Models(scene).size(), 2u);
  for (vtkRPModelNode* model : {display, haptic}) {
    EXPECT_EQ(model->GetTissueClass(), "bone");
    long boundary = -1, nonManifold = -1;
    rp::CountBadEdges(model->GetPolyData(), boundary, nonManifold);
    EXPECT_EQ(boundary, 0) << model->GetName();
    EXPECT_EQ(nonManifold, 0) << model->GetName();
    double meshVolume = 0, area = 0;
    rp::MeshVolumeAndArea(model->GetPolyData(), meshVolume, area);
    EXPECT_NEAR(meshVolume / ballVolume, 1.0, 0.05) << model->GetName();
  }
  EXPECT_TRUE(display->GetVisibility());
  EXPECT_TRUE(haptic->GetHaptic());
  EXPECT_LE(haptic->GetPolyData()->GetNumberOfCells(), 5000 * 1.2);
  EXPECT_TRUE(panel.StatusText().contains("watertight")) << panel.StatusText().toStdString();

  // Create again: the models are replaced, not duplicated.
  QTest::mouseClick(panel.CreateModelsButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_EQ(Models(scene).size(), 2u);

  // Region growing from a fiducial at the centre: the same ball as a second segment.
  vtkNew<vtkRPFiducialListNode> seeds;
  seeds->SetName("Seeds");
  scene->AddNode(seeds);
  seeds->AddControlPoint(kCentre);
  ASSERT_EQ(panel.SeedsCombo->count(), 2);  // "(no seeds)" + Seeds
  panel.SeedsCombo->setCurrentIndex(1);
  panel.MethodCombo->setCurrentIndex(qRPSegmentationToMeshPanel::RegionGrowing);
  panel.LowerSpin->setValue(500);
  panel.UpperSpin->setValue(1500);
  panel.SegmentNameEdit->setText("grown");
  panel.TissueCombo->setCurrentText("cartilage");
  // Overwrite is off: the voxels already labelled "bone" are not taken, so grow into a fresh one.
  QTest::mouseClick(panel.NewSegmentationButton, Qt::LeftButton);
  ASSERT_NE(panel.CurrentSegmentation(), segmentation);
  QTest::mouseClick(panel.ApplyButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_EQ(CountLabel(panel.CurrentSegmentation(), "grown"), sphereVoxels);
  EXPECT_EQ(panel.CurrentSegmentation()->GetSegmentByID("grown")->TissueClass, "cartilage");

  // Edits of the current segment: one ball, no holes, so keep largest and fill holes keep every
  // voxel; closing never removes voxels, opening never adds any.
  ASSERT_EQ(panel.CurrentSegmentID(), "grown");
  QTest::mouseClick(panel.KeepLargestButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_TRUE(panel.StatusText().contains("largest of 1 components")) << panel.StatusText().toStdString();
  EXPECT_EQ(CountLabel(panel.CurrentSegmentation(), "grown"), sphereVoxels);
  QTest::mouseClick(panel.FillHolesButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_EQ(CountLabel(panel.CurrentSegmentation(), "grown"), sphereVoxels);
  QTest::mouseClick(panel.OpeningButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  const long opened = CountLabel(panel.CurrentSegmentation(), "grown");
  EXPECT_LE(opened, sphereVoxels);
  EXPECT_GT(opened, sphereVoxels * 9 / 10);
  QTest::mouseClick(panel.ClosingButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_GE(CountLabel(panel.CurrentSegmentation(), "grown"), opened);
  // A segment added elsewhere (another module, a script) shows up in the segment list.
  vtkRPSegmentationNode::Segment added;
  added.ID = "added";
  added.LabelValue = panel.CurrentSegmentation()->GetUnusedLabelValue();
  panel.CurrentSegmentation()->SetSegment(added);
  EXPECT_EQ(panel.SegmentCombo->count(), 2);
  EXPECT_GE(panel.SegmentCombo->findData("added"), 0);
  EXPECT_EQ(panel.CurrentSegmentID(), "grown");  // the selection is kept
  // Re-apply restores the exact ball.
  QTest::mouseClick(panel.ApplyButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  EXPECT_EQ(CountLabel(panel.CurrentSegmentation(), "grown"), sphereVoxels);

  // A seed outside the ball's intensity range is refused by name, the segment is kept.
  seeds->AddControlPoint(kOrigin);
  QTest::mouseClick(panel.ApplyButton, Qt::LeftButton);
  EXPECT_TRUE(panel.HasError());
  EXPECT_TRUE(panel.StatusText().startsWith("Apply failed")) << panel.StatusText().toStdString();
  EXPECT_EQ(CountLabel(panel.CurrentSegmentation(), "grown"), sphereVoxels);

  // A picture of the panel (with the red error) to look at.
  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  EXPECT_TRUE(panel.grab().save(QString(ROBOPLAN_TEST_OUTPUT_DIR) + "/SegmentationToMeshPanel.png"));
}

TEST(SegmentationToMeshPanel, LabelmapVolumeBecomesOneSegmentPerLabel) {
  App();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPSegmentationToMeshLogic> logic;
  logic->SetScene(scene);
  qRPSegmentationToMeshPanel panel(logic);
  // A labelmap volume: the sphere is label 2, a slab is label 5.
  long sphereVoxels = 0;
  auto volume = MakeSphereCT(sphereVoxels);
  volume->SetName("knee-label");
  auto* v = static_cast<short*>(volume->GetImageData()->GetScalarPointer());
  long slab = 0;
  for (vtkIdType n = 0; n < volume->GetImageData()->GetNumberOfPoints(); ++n) {
    v[n] = v[n] > 0 ? 2 : (n < kDim * kDim * 3 ? 5 : 0);
    slab += v[n] == 5;
  }
  scene->AddNode(volume);
  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  const QString tablePath = QString(ROBOPLAN_TEST_OUTPUT_DIR) + "/panel-labels.ctbl";
  {
    FILE* f = std::fopen(tablePath.toStdString().c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("0 Background 0 0 0 0\n2 femur 255 0 0 255\n", f);
    std::fclose(f);
  }
  panel.LabelTableEdit->setText(tablePath);
  QTest::mouseClick(panel.LabelmapButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  vtkRPSegmentationNode* segmentation = panel.CurrentSegmentation();
  ASSERT_NE(segmentation, nullptr);
  ASSERT_EQ(segmentation->GetNumberOfSegments(), 2);
  EXPECT_EQ(segmentation->GetNthSegment(0).Name, "femur");
  EXPECT_DOUBLE_EQ(segmentation->GetNthSegment(0).Color[0], 1.0);
  EXPECT_EQ(segmentation->GetNthSegment(1).Name, "Label 5");  // not in the table
  EXPECT_EQ(CountLabel(segmentation, "femur"), sphereVoxels);
  EXPECT_EQ(CountLabel(segmentation, "Label 5"), slab);
  EXPECT_NE(segmentation->GetImageData(), volume->GetImageData()) << "the volume keeps its own voxels";
  EXPECT_EQ(panel.SegmentCombo->count(), 2);
  EXPECT_TRUE(panel.StatusText().contains("femur")) << panel.StatusText().toStdString();

  // A CT is not a labelmap: a red error naming why, no segmentation added.
  auto ct = MakeSphereCT(sphereVoxels);
  scene->AddNode(ct);
  panel.VolumeCombo->setCurrentIndex(panel.VolumeCombo->findText("SphereCT"));
  QTest::mouseClick(panel.LabelmapButton, Qt::LeftButton);
  EXPECT_TRUE(panel.HasError());
  EXPECT_TRUE(panel.StatusText().contains("negative")) << panel.StatusText().toStdString();
  EXPECT_EQ(scene->GetNodesByClass("vtkRPSegmentationNode").size(), 1u);
  // A broken label table is named.
  panel.VolumeCombo->setCurrentIndex(panel.VolumeCombo->findText("knee-label"));
  panel.LabelTableEdit->setText(tablePath + ".missing");
  QTest::mouseClick(panel.LabelmapButton, Qt::LeftButton);
  EXPECT_TRUE(panel.HasError());
  EXPECT_TRUE(panel.StatusText().contains(".missing")) << panel.StatusText().toStdString();
}

TEST(SegmentationToMeshPanel, BonesOneByOneNamedBySeedLabels) {
  App();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPSegmentationToMeshLogic> logic;
  logic->SetScene(scene);
  qRPSegmentationToMeshPanel panel(logic);
  long sphereVoxels = 0;
  auto ct = MakeSphereCT(sphereVoxels);
  scene->AddNode(ct);
  // Without seeds: one bone, "Bone 1", the ball's voxels less its partial-volume edge.
  QTest::mouseClick(panel.SplitBonesButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  vtkRPSegmentationNode* bones = panel.CurrentSegmentation();
  ASSERT_NE(bones, nullptr);
  ASSERT_EQ(bones->GetNumberOfSegments(), 1);
  EXPECT_EQ(bones->GetNthSegment(0).ID, "Bone 1");
  EXPECT_EQ(bones->GetNthSegment(0).TissueClass, "bone");
  EXPECT_NEAR(static_cast<double>(CountLabel(bones, "Bone 1")) / sphereVoxels, 1.0, 0.05);
  // A seed list: a labelled point names the bone; a generated label does not.
  vtkNew<vtkRPFiducialListNode> seeds;
  seeds->SetName("Seeds");
  scene->AddNode(seeds);
  seeds->AddControlPoint(kCentre, "humerus");
  panel.SeedsCombo->setCurrentIndex(panel.SeedsCombo->findText("Seeds"));
  QTest::mouseClick(panel.SplitBonesButton, Qt::LeftButton);
  ASSERT_FALSE(panel.HasError()) << panel.StatusText().toStdString();
  ASSERT_NE(panel.CurrentSegmentation(), bones) << "a new segmentation each time";
  EXPECT_EQ(panel.CurrentSegmentation()->GetNthSegment(0).ID, "humerus");
  EXPECT_TRUE(panel.StatusText().contains("named by seed")) << panel.StatusText().toStdString();
  seeds->SetNthControlPointLabel(0, "Seeds-1");
  QTest::mouseClick(panel.SplitBonesButton, Qt::LeftButton);
  EXPECT_EQ(panel.CurrentSegmentation()->GetNthSegment(0).ID, "Bone 1");
  // A seed off bone: a red error naming it.
  const double outside[3] = {kOrigin[0] + 1, kOrigin[1] + 1, kOrigin[2] + 1};
  seeds->AddControlPoint(outside, "skull");
  QTest::mouseClick(panel.SplitBonesButton, Qt::LeftButton);
  EXPECT_TRUE(panel.HasError());
  EXPECT_TRUE(panel.StatusText().contains("'skull' is not on bone")) << panel.StatusText().toStdString();
}
