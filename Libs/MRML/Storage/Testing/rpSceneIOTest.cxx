// Scene save/load round trips (bit-identical data), atomic saves, and scenes with missing or
// corrupt data files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include "rpAtomicFile.h"
#include "rpModelIO.h"
#include "rpNodeStorage.h"
#include "rpSceneIO.h"
#include "rpTestOutput.h"
#include "rpVolumeIO.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"

namespace fs = std::filesystem;

using rptest::TestDir;

namespace {

// A CT-like volume with an oblique, LPS-flipped geometry and a deterministic pattern.
vtkSmartPointer<vtkRPScalarVolumeNode> MakeVolume() {
  auto volume = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
  volume->SetName("CT");
  vtkNew<vtkImageData> image;
  image->SetDimensions(7, 5, 4);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* voxels = static_cast<short*>(image->GetScalarPointer());
  for (int i = 0; i < 7 * 5 * 4; ++i) voxels[i] = static_cast<short>((i * 37) % 3001 - 1000);
  volume->SetImageData(image);
  const double c = std::cos(0.3), s = std::sin(0.3);
  const double spacing[3] = {0.8, 0.8, 2.5}, origin[3] = {-12.5, 40.25, -7};
  const double directions[3][3] = {{c, s, 0}, {-s, c, 0}, {0, 0, 1}};
  volume->SetGeometry(spacing, origin, directions);
  volume->SetWindowLevel(1500, 300);
  return volume;
}

vtkSmartPointer<vtkRPModelNode> MakeModel() {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(10, -20, 30);
  sphere->SetRadius(15);
  sphere->Update();
  auto model = vtkSmartPointer<vtkRPModelNode>::New();
  model->SetName("Femur");
  model->SetPolyData(sphere->GetOutput());
  model->SetColor(0.9, 0.85, 0.7);
  model->SetOpacity(0.6);
  model->SetTissueClass("bone");
  model->SetHaptic(true);
  return model;
}

}  // namespace

TEST(VolumeIO, NrrdAndNiftiRoundTripsAreExact) {
  const fs::path dir = TestDir("volumes");
  auto volume = MakeVolume();
  for (const std::string ext : {".nrrd", ".nii.gz", ".mha"}) {
    const std::string path = (dir / ("ct" + ext)).string();
    std::string error;
    ASSERT_TRUE(rp::WriteVolumeFile(path, volume, error)) << error;
    auto loaded = vtkSmartPointer<vtkRPScalarVolumeNode>::New();
    ASSERT_TRUE(rp::ReadVolumeFile(path, loaded.GetPointer(), error)) << error;
    int dims[3];
    loaded->GetImageData()->GetDimensions(dims);
    EXPECT_EQ(dims[0], 7);
    EXPECT_EQ(dims[2], 4);
    EXPECT_EQ(loaded->GetImageData()->GetScalarType(), VTK_SHORT);
    EXPECT_EQ(std::memcmp(loaded->GetImageData()->GetScalarPointer(), volume->GetImageData()->GetScalarPointer(),
                          7 * 5 * 4 * sizeof(short)),
              0)
        << ext;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        EXPECT_NEAR(loaded->GetIJKToRASMatrix()->GetElement(i, j), volume->GetIJKToRASMatrix()->GetElement(i, j),
                    1e-5)
            << ext << " element " << i << "," << j;
  }
}

TEST(VolumeIO, NrrdHeaderIsLPS) {
  // A hand-written NRRD (as Slicer writes them): LPS space, origin and directions in LPS.
  const fs::path dir = TestDir("nrrd-header");
  const std::string path = (dir / "tiny.nrrd").string();
  std::ofstream out(path, std::ios::binary);
  out << "NRRD0004\ntype: unsigned char\ndimension: 3\nspace: left-posterior-superior\nsizes: 2 2 1\n"
         "space directions: (2,0,0) (0,3,0) (0,0,4)\nkinds: domain domain domain\nendian: little\n"
         "encoding: raw\nspace origin: (10,20,30)\n\n";
  out.write("\x01\x02\x03\x04", 4);
  out.close();
  vtkNew<vtkImageData> image;
  vtkNew<vtkMatrix4x4> ijkToRAS;
  rp::VolumeFileData data;
  data.Image = image;
  data.IJKToRAS = ijkToRAS;
  std::string error;
  ASSERT_TRUE(rp::ReadVolumeFile(path, data, error)) << error;
  // RAS = diag(-1,-1,1) · LPS.
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(0, 0), -2);
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(1, 1), -3);
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(2, 2), 4);
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(0, 3), -10);
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(1, 3), -20);
  EXPECT_DOUBLE_EQ(ijkToRAS->GetElement(2, 3), 30);
  EXPECT_EQ(*static_cast<unsigned char*>(image->GetScalarPointer(1, 1, 0)), 4);
}

TEST(VolumeIO, BadFilesGiveClearErrors) {
  const fs::path dir = TestDir("bad-volumes");
  std::string error;
  auto node = MakeVolume();
  EXPECT_FALSE(rp::ReadVolumeFile((dir / "missing.nrrd").string(), node.GetPointer(), error));
  EXPECT_NE(error.find("missing.nrrd"), std::string::npos);
  std::ofstream((dir / "truncated.nrrd").string()) << "NRRD0004\ntype: short\ndimension: 3\nsizes: 100 100 100\n"
                                                      "encoding: raw\n\n\x01\x02";
  EXPECT_FALSE(rp::ReadVolumeFile((dir / "truncated.nrrd").string(), node.GetPointer(), error));
  EXPECT_NE(error.find("truncated.nrrd"), std::string::npos);
  int dims[3];
  node->GetImageData()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 7);  // the node kept its image
  EXPECT_FALSE(rp::ReadVolumeFile((dir / "volume.xyz").string(), node.GetPointer(), error));
}

TEST(ModelIO, EveryFormatRoundTripsInRASAndWritesLPS) {
  const fs::path dir = TestDir("models");
  auto model = MakeModel();
  for (const std::string ext : {".vtp", ".vtk", ".stl", ".ply", ".obj"}) {
    const std::string path = (dir / ("femur" + ext)).string();
    std::string error;
    ASSERT_TRUE(rp::SaveDataFile(model, path, error)) << error;
    vtkNew<vtkRPScene> scene;
    auto* loaded = vtkRPModelNode::SafeDownCast(rp::LoadDataFile(scene, path, error));
    ASSERT_NE(loaded, nullptr) << error;
    double bounds[6];
    loaded->GetPolyData()->GetBounds(bounds);
    EXPECT_NEAR(0.5 * (bounds[0] + bounds[1]), 10, 1e-3) << ext;   // R stays R after LPS round trip
    EXPECT_NEAR(0.5 * (bounds[2] + bounds[3]), -20, 1e-3) << ext;
    EXPECT_NEAR(0.5 * (bounds[4] + bounds[5]), 30, 1e-3) << ext;
    if (ext == ".stl" || ext == ".vtk" || ext == ".ply") {
      // Slicer reads the coordinate system from the header comment.
      std::ifstream in(path, std::ios::binary);
      std::string head(1024, '\0');
      in.read(&head[0], 1024);
      EXPECT_NE(head.find("SPACE=LPS"), std::string::npos) << ext;
    }
  }
}

TEST(ModelIO, VtpHoldsRawZlibBlocksThatVTKReadsBackExactly) {
  // libdeflate writes the blocks; the file must name the compressor that reads them (zlib's) and
  // read back bit for bit through plain vtkXMLPolyDataReader, as Slicer and ParaView read it.
  const fs::path dir = TestDir("vtp-zlib");
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(400);
  sphere->SetPhiResolution(400);  // ~160,000 triangles: many 32 KiB blocks
  sphere->Update();
  const std::string path = (dir / "sphere.vtp").string();
  std::string error;
  ASSERT_TRUE(rp::WriteModelFile(path, sphere->GetOutput(), error)) << error;
  std::string contents;
  ASSERT_TRUE(rp::ReadFile(path, contents, error)) << error;
  const std::string head = contents.substr(0, 2000);
  EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << head;
  EXPECT_NE(contents.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* read = reader->GetOutput();
  vtkPolyData* written = sphere->GetOutput();
  ASSERT_EQ(read->GetNumberOfPoints(), written->GetNumberOfPoints());
  ASSERT_EQ(read->GetNumberOfPolys(), written->GetNumberOfPolys());
  // The file is LPS: x and y flipped, z kept, every coordinate exact in float.
  for (vtkIdType i = 0; i < written->GetNumberOfPoints(); ++i) {
    double a[3], b[3];
    written->GetPoint(i, a), read->GetPoint(i, b);
    ASSERT_EQ(b[0], -a[0]) << i;
    ASSERT_EQ(b[1], -a[1]) << i;
    ASSERT_EQ(b[2], a[2]) << i;
  }
  // Compressed: less than half the size of the same file written uncompressed.
  vtkNew<vtkXMLPolyDataWriter> plain;
  plain->SetInputData(written);
  plain->SetFileName((dir / "plain.vtp").string().c_str());
  plain->SetDataModeToAppended();
  plain->EncodeAppendedDataOff();
  plain->SetCompressorTypeToNone();
  ASSERT_EQ(plain->Write(), 1);
  EXPECT_LT(contents.size(), fs::file_size(dir / "plain.vtp") / 2);
}

TEST(SceneIO, RoundTripOfEveryNodeTypeIsIdentical) {
  const fs::path dir = TestDir("scene");
  vtkNew<vtkRPScene> scene;
  auto volume = MakeVolume();
  auto model = MakeModel();
  vtkNew<vtkRPLinearTransformNode> trackerToRAS;
  trackerToRAS->SetName("TrackerToRAS");
  const double m[16] = {0, -1, 0, 10.125, 1, 0, 0, -20.5, 0, 0, 1, 30.75, 0, 0, 0, 1};
  trackerToRAS->SetMatrixTransformToParent(m);
  vtkNew<vtkRPTrackedToolNode> stylus;
  stylus->SetName("StylusToTracker");
  stylus->SetStatus(vtkRPTrackedToolNode::StatusMissing);
  stylus->SetTimestamp(12.5);
  scene->AddNode(volume);
  scene->AddNode(model);
  scene->AddNode(trackerToRAS);
  scene->AddNode(stylus);
  ASSERT_TRUE(stylus->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  ASSERT_TRUE(model->SetAndObserveTransformNodeID(trackerToRAS->GetID()));
  model->SetAttribute("Haptic.Mesh", "coarse");
  vtkNew<vtkRPFiducialListNode> fiducials;
  fiducials->SetName("ImageLandmarks");
  const double p1[3] = {12.25, -3.5, 40.125}, p2[3] = {-7, 8, 9};
  fiducials->AddControlPoint(p1, "medial epicondyle");
  fiducials->AddControlPoint(p2, "tibial tuberosity");
  fiducials->SetNthControlPointSelected(1, false);
  scene->AddNode(fiducials);
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName("Bones");
  vtkNew<vtkImageData> labels;
  labels->SetDimensions(6, 5, 4);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* l = static_cast<unsigned char*>(labels->GetScalarPointer());
  for (int i = 0; i < 6 * 5 * 4; ++i) l[i] = static_cast<unsigned char>(i % 3);
  segmentation->SetImageData(labels);
  segmentation->SetIJKToRASMatrix(volume->GetIJKToRASMatrix());
  vtkRPSegmentationNode::Segment femur;
  femur.ID = "femur";
  femur.Name = "Femur";
  femur.LabelValue = 1;
  femur.TissueClass = "bone";
  femur.Color[0] = 0.9;
  segmentation->SetSegment(femur);
  vtkRPSegmentationNode::Segment acl;
  acl.ID = "acl";
  acl.Name = "ACL";
  acl.LabelValue = 2;
  acl.TissueClass = "ligament";
  segmentation->SetSegment(acl);
  scene->AddNode(segmentation);

  const std::string sceneFile = (dir / "knee.rpscene").string();
  std::string error;
  ASSERT_TRUE(rp::SaveScene(scene, sceneFile, error)) << error;

  vtkNew<vtkRPScene> loaded;
  const rp::SceneLoadReport report = rp::LoadScene(loaded, sceneFile);
  ASSERT_TRUE(report.Ok) << report.Error;
  EXPECT_TRUE(report.Problems.empty()) << report.Problems.front();
  EXPECT_EQ(report.NodesLoaded, 6);
  // One data file per node, in the formats Slicer reads.
  for (const char* file : {"CT.nrrd", "Femur.vtp", "TrackerToRAS.tfm", "StylusToTracker.tfm",
                           "ImageLandmarks.mrk.json", "Bones.seg.nrrd"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }

  auto* v = vtkRPScalarVolumeNode::SafeDownCast(loaded->GetFirstNodeByName("CT"));
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(std::memcmp(v->GetImageData()->GetScalarPointer(), volume->GetImageData()->GetScalarPointer(),
                        7 * 5 * 4 * sizeof(short)),
            0);
  EXPECT_DOUBLE_EQ(v->GetWindow(), 1500);
  EXPECT_DOUBLE_EQ(v->GetLevel(), 300);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(v->GetIJKToRASMatrix()->GetElement(i, j), volume->GetIJKToRASMatrix()->GetElement(i, j), 1e-12);

  auto* mo = vtkRPModelNode::SafeDownCast(loaded->GetFirstNodeByName("Femur"));
  ASSERT_NE(mo, nullptr);
  ASSERT_EQ(mo->GetPolyData()->GetNumberOfPoints(), model->GetPolyData()->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mo->GetPolyData()->GetNumberOfPoints(); ++i) {
    double a[3], b[3];
    mo->GetPolyData()->GetPoint(i, a);
    model->GetPolyData()->GetPoint(i, b);
    ASSERT_EQ(a[0], b[0]);  // negation twice is exact in floating point
    ASSERT_EQ(a[1], b[1]);
    ASSERT_EQ(a[2], b[2]);
  }
  EXPECT_EQ(mo->GetTissueClass(), "bone");
  EXPECT_TRUE(mo->GetHaptic());
  EXPECT_DOUBLE_EQ(mo->GetOpacity(), 0.6);
  EXPECT_EQ(mo->GetAttribute("Haptic.Mesh"), "coarse");

  auto* t = vtkRPLinearTransformNode::SafeDownCast(loaded->GetFirstNodeByName("TrackerToRAS"));
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(mo->GetParentTransformNode(), t);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(t->GetMatrixTransformToParent()->GetElement(i / 4, i % 4), m[i], 1e-12);
  auto* st = vtkRPTrackedToolNode::SafeDownCast(loaded->GetFirstNodeByName("StylusToTracker"));
  ASSERT_NE(st, nullptr);
  EXPECT_EQ(st->GetStatus(), vtkRPTrackedToolNode::StatusMissing);
  EXPECT_DOUBLE_EQ(st->GetTimestamp(), 12.5);
  EXPECT_EQ(st->GetParentTransformNode(), t);

  auto* f = vtkRPFiducialListNode::SafeDownCast(loaded->GetFirstNodeByName("ImageLandmarks"));
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(f->GetNumberOfControlPoints(), 2);
  EXPECT_EQ(f->GetNthControlPoint(0).Label, "medial epicondyle");
  for (int i = 0; i < 3; ++i) EXPECT_EQ(f->GetNthControlPoint(0).Position[i], p1[i]);
  EXPECT_FALSE(f->GetNthControlPoint(1).Selected);

  auto* sg = vtkRPSegmentationNode::SafeDownCast(loaded->GetFirstNodeByName("Bones"));
  ASSERT_NE(sg, nullptr);
  ASSERT_EQ(sg->GetNumberOfSegments(), 2);
  ASSERT_NE(sg->GetSegmentByID("acl"), nullptr);
  EXPECT_EQ(sg->GetSegmentByID("acl")->TissueClass, "ligament");
  EXPECT_EQ(sg->GetSegmentByID("acl")->LabelValue, 2);
  int dims[3];
  sg->GetImageData()->GetDimensions(dims);
  ASSERT_EQ(dims[0] * dims[1] * dims[2], 6 * 5 * 4);
  // The file may store the labelmap cropped to the segments' extent; compare by RAS position.
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(*static_cast<unsigned char*>(sg->GetImageData()->GetScalarPointer(i, j, k)),
                  *static_cast<unsigned char*>(labels->GetScalarPointer(i, j, k)));
      }
}

TEST(SceneIO, MissingAndCorruptDataFilesAreReportedByNameAndTheRestLoads) {
  const fs::path dir = TestDir("scene-damaged");
  vtkNew<vtkRPScene> scene;
  auto volume = MakeVolume();
  auto model = MakeModel();
  auto model2 = MakeModel();
  model2->SetName("Tibia");
  scene->AddNode(volume);
  scene->AddNode(model);
  scene->AddNode(model2);
  const std::string sceneFile = (dir / "knee.rpscene").string();
  std::string error;
  ASSERT_TRUE(rp::SaveScene(scene, sceneFile, error)) << error;
  fs::remove(dir / "CT.nrrd");
  std::ofstream(dir / "Tibia.vtp", std::ios::trunc) << "<VTKFile type=\"PolyData\"> garbage";

  vtkNew<vtkRPScene> loaded;
  vtkNew<vtkRPModelNode> alreadyThere;
  alreadyThere->SetName("Patella");
  loaded->AddNode(alreadyThere);
  const rp::SceneLoadReport report = rp::LoadScene(loaded, sceneFile);
  ASSERT_TRUE(report.Ok);
  EXPECT_EQ(report.NodesLoaded, 1);
  ASSERT_EQ(report.Problems.size(), 2u);
  EXPECT_NE(report.Problems[0].find("CT.nrrd"), std::string::npos);
  EXPECT_NE(report.Problems[0].find("missing"), std::string::npos);
  EXPECT_NE(report.Problems[1].find("Tibia.vtp"), std::string::npos);
  EXPECT_NE(loaded->GetFirstNodeByName("Femur"), nullptr);
  EXPECT_NE(loaded->GetFirstNodeByName("Patella"), nullptr);  // nothing already loaded is lost
  EXPECT_EQ(loaded->GetNumberOfNodes(), 2);

  // A scene file that is not a scene: refused, nothing changes.
  std::ofstream(dir / "bad.rpscene") << "{\"format\": \"something else\"}";
  const rp::SceneLoadReport bad = rp::LoadScene(loaded, (dir / "bad.rpscene").string());
  EXPECT_FALSE(bad.Ok);
  EXPECT_NE(bad.Error.find("not a RoboPlan scene"), std::string::npos);
  EXPECT_EQ(loaded->GetNumberOfNodes(), 2);
  std::ofstream(dir / "future.rpscene") << "{\"format\": \"RoboPlan scene\", \"version\": 99, \"nodes\": []}";
  EXPECT_FALSE(rp::LoadScene(loaded, (dir / "future.rpscene").string()).Ok);
  // Wrong JSON types (the first scene reader threw out of LoadScene on a number as an entry or a
  // number as dataFile): each bad entry is reported by name and skipped, the good one loads.
  std::ofstream(dir / "types.rpscene")
      << R"({"format": "RoboPlan scene", "version": 1, "nodes": [
            7,
            {"class": "vtkRPModelNode", "id": "m1", "name": "Bad file", "dataFile": 3},
            {"class": "vtkRPModelNode", "id": "m2", "name": "Bad attributes", "attributes": {"a": [1]}},
            {"class": "vtkRPLinearTransformNode", "id": "t1", "name": "Good", "references": {}}]})";
  const rp::SceneLoadReport types = rp::LoadScene(loaded, (dir / "types.rpscene").string());
  ASSERT_TRUE(types.Ok) << types.Error;
  EXPECT_EQ(types.NodesLoaded, 1);
  ASSERT_EQ(types.Problems.size(), 3u);
  EXPECT_NE(types.Problems[1].find("Bad file"), std::string::npos) << types.Problems[1];
  EXPECT_NE(types.Problems[1].find("dataFile"), std::string::npos) << types.Problems[1];
  EXPECT_NE(types.Problems[2].find("attributes"), std::string::npos) << types.Problems[2];
  std::ofstream(dir / "version-text.rpscene") << R"({"format": "RoboPlan scene", "version": "1", "nodes": []})";
  EXPECT_FALSE(rp::LoadScene(loaded, (dir / "version-text.rpscene").string()).Ok);
}

TEST(SceneIO, AFailedSaveKeepsTheLastGoodSceneFile) {
  const fs::path dir = TestDir("scene-atomic");
  vtkNew<vtkRPScene> scene;
  scene->AddNode(MakeModel());
  const std::string sceneFile = (dir / "knee.rpscene").string();
  std::string error;
  ASSERT_TRUE(rp::SaveScene(scene, sceneFile, error)) << error;
  std::string before;
  ASSERT_TRUE(rp::ReadFile(sceneFile, before, error));
  // A model with no points cannot be written: the save fails before touching the scene file.
  vtkNew<vtkRPModelNode> empty;
  empty->SetName("Empty");
  scene->AddNode(empty);
  EXPECT_FALSE(rp::SaveScene(scene, sceneFile, error));
  EXPECT_NE(error.find("Empty"), std::string::npos);
  std::string after;
  ASSERT_TRUE(rp::ReadFile(sceneFile, after, error));
  EXPECT_EQ(before, after);
}

// The views are scene state: slice planes, field of view, layers, the followed tool and the
// layout come back with the scene, into the scene's own view nodes (no duplicates).
TEST(SceneIO, SliceNodesAndLayoutRoundTripIntoTheViewsNodes) {
  const fs::path dir = TestDir("views");
  vtkNew<vtkRPScene> scene;
  auto ct = MakeVolume();
  scene->AddNode(ct);
  vtkNew<vtkRPLinearTransformNode> stylus;
  stylus->SetName("StylusTipToStylus");
  scene->AddNode(stylus);
  const auto nodes = vtkRPSliceNode::GetOrAddDefaultSliceNodes(scene);
  ASSERT_EQ(nodes.size(), 3u);
  const double point[3] = {-4.5, 12.25, 33};
  vtkRPSliceNode::JumpAllSlices(scene, point);
  nodes[0]->SetFieldOfView(150, 110);
  nodes[0]->SetXYOrigin(5, -6);
  nodes[0]->SetBackgroundVolumeID(ct->GetID());
  nodes[0]->SetForegroundOpacity(0.3);
  nodes[1]->SetOrientationToCoronal();  // a user's choice: Yellow shows a coronal plane
  nodes[1]->JumpSlice(point);
  nodes[2]->SetSliceVisible(false);
  ASSERT_TRUE(nodes[2]->SetAndObserveFollowNodeID(stylus->GetID()));
  vtkRPLayoutNode::GetOrAddLayoutNode(scene)->SetViewArrangement(vtkRPLayoutNode::OneUpSagittal);
  std::string error;
  ASSERT_TRUE(rp::SaveScene(scene, (dir / "views.rpscene").string(), error)) << error;

  // A viewer's scene already has its view nodes (reset); a plain scene has none.
  for (bool withViews : {true, false}) {
    vtkNew<vtkRPScene> loaded;
    if (withViews) {
      vtkRPSliceNode::GetOrAddDefaultSliceNodes(loaded);
      vtkRPLayoutNode::GetOrAddLayoutNode(loaded);
    }
    const rp::SceneLoadReport report = rp::LoadScene(loaded, (dir / "views.rpscene").string());
    ASSERT_TRUE(report.Ok) << report.Error;
    EXPECT_TRUE(report.Problems.empty());
    const auto views = vtkRPSliceNode::GetSliceNodes(loaded);
    ASSERT_EQ(views.size(), 3u) << "with views: " << withViews;
    vtkRPSliceNode* red = vtkRPSliceNode::GetSliceNode(loaded, "Red");
    vtkRPSliceNode* yellow = vtkRPSliceNode::GetSliceNode(loaded, "Yellow");
    vtkRPSliceNode* green = vtkRPSliceNode::GetSliceNode(loaded, "Green");
    ASSERT_TRUE(red && yellow && green);
    EXPECT_DOUBLE_EQ(red->GetSliceOffset(), 33);
    EXPECT_DOUBLE_EQ(red->GetFieldOfView()[0], 150);
    EXPECT_DOUBLE_EQ(red->GetXYOrigin()[1], -6);
    EXPECT_DOUBLE_EQ(red->GetForegroundOpacity(), 0.3);
    auto* background = loaded->GetNodeByID(red->GetBackgroundVolumeID());
    ASSERT_NE(background, nullptr);
    EXPECT_EQ(background->GetName(), "CT");
    EXPECT_EQ(yellow->GetOrientation(), "Coronal");
    EXPECT_DOUBLE_EQ(yellow->GetSliceOffset(), 12.25);
    EXPECT_FALSE(green->GetSliceVisible());
    auto* followed = loaded->GetNodeByID(green->GetFollowNodeID());
    ASSERT_NE(followed, nullptr);
    EXPECT_EQ(followed->GetName(), "StylusTipToStylus");
    // Following resumes after loading: moving the stylus moves the Green slice.
    vtkNew<vtkMatrix4x4> moved;
    moved->SetElement(1, 3, -50);
    vtkRPLinearTransformNode::SafeDownCast(followed)->SetMatrixTransformToParent(moved);
    EXPECT_DOUBLE_EQ(green->GetSliceOffset(), -50);
    EXPECT_EQ(vtkRPLayoutNode::GetOrAddLayoutNode(loaded)->GetViewArrangement(), vtkRPLayoutNode::OneUpSagittal);
  }
}
