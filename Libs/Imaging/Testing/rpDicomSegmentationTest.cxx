// Segmentations the DICOM way, on the real knee CT (shared/data/knee-ct-vhf) and its bone labels:
// - SEG written here (DCMTK's dcmseg) is read back voxel-exact, checked by DCMTK's dcmdump and
//   by pydicom as an independent reader (segments, frames, positions, referenced series, voxels);
// - a fractional SEG made from it by pydicom (an independent writer) reads back thresholded;
// - an RTSTRUCT of the bones (contours per slice from vtkMarchingSquares, written by pydicom) is
//   rasterized back within half a voxel (Dice, distance of every differing voxel to the contour).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMarchingSquares.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStripper.h>

#include "rpDataLoader.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "rpDicomSeries.h"
#include "rpDicomPython.h"
#include "rpDicomTestTools.h"
#include "rpSharedData.h"
#include "rpImagingReaders.h"
#include "rpVolumeFiles.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace {

using rp::testing::CheckSegScript;
using rp::testing::DeflateScript;
using rp::testing::FractionalScript;
using rp::testing::HavePydicom;
using rp::testing::RtStructScript;
using rp::testing::RunPython;
using rp::testing::SliceContours;
using rp::testing::Slurp;

struct Knee {
  std::string Dicom;
  rp::ImageVolume Labels;
  vtkNew<vtkRPSegmentationNode> Node;
};

// The knee's labels as a segmentation node on the CT's grid (labels.nrrd shares the grid).
void LoadKnee(Knee& knee) {
  knee.Dicom = rptest::SharedDataPath("knee-ct-vhf/dicom");
  std::string error;
  ASSERT_TRUE(rp::ReadVolume(rptest::SharedDataPath("knee-ct-vhf/labels.nrrd"), knee.Labels, error)) << error;
  rp::ImageVolume ct;
  ASSERT_TRUE(rp::ReadDicomVolume(knee.Dicom, ct, error)) << error;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      ASSERT_NEAR(knee.Labels.IJKToRAS->GetElement(r, c), ct.IJKToRAS->GetElement(r, c), 1e-4);
  rp::CopyToNode(knee.Labels, knee.Node.GetPointer());
  const char* names[3] = {"Tibia", "Fibula", "Patella"};
  const char* ids[3] = {"tibia", "fibula", "patella"};
  const double colors[3][3] = {{0.9, 0.85, 0.7}, {0.2, 0.6, 0.9}, {0.8, 0.3, 0.3}};
  for (int l = 0; l < 3; ++l) {
    rp::Segment s;
    s.ID = ids[l];
    s.Name = names[l];
    s.LabelValue = l + 1;
    std::copy(colors[l], colors[l] + 3, s.Color);
    s.TissueClass = "bone";
    knee.Node->SetSegment(s);
  }
}

std::map<int, size_t> CountLabels(vtkImageData* image) {
  std::map<int, size_t> counts;
  vtkDataArray* a = image->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) ++counts[static_cast<int>(a->GetComponent(i, 0))];
  return counts;
}

size_t DifferingVoxels(vtkImageData* a, vtkImageData* b) {
  vtkDataArray* x = a->GetPointData()->GetScalars();
  vtkDataArray* y = b->GetPointData()->GetScalars();
  size_t differing = 0;
  for (vtkIdType i = 0; i < x->GetNumberOfTuples(); ++i) differing += x->GetComponent(i, 0) != y->GetComponent(i, 0);
  return differing;
}

}  // namespace

TEST(DicomSegmentation, KneeLabelsWrittenAsSegReadBackVoxelExact) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  Knee knee;
  ASSERT_NO_FATAL_FAILURE(LoadKnee(knee));
  const fs::path dir = rp::testing::Scratch("seg-knee");
  const fs::path seg = dir / "knee-bones.seg.dcm";
  std::string error;
  ASSERT_TRUE(rp::WriteDicomSegmentation(knee.Node, knee.Dicom, seg.string(), error)) << error;

  // Read back on the CT's grid: every voxel, every segment's name, colour and tissue class.
  vtkNew<vtkRPSegmentationNode> back;
  std::vector<std::string> warnings;
  ASSERT_TRUE(rp::ReadDicomSegmentation(seg.string(), back, error, knee.Dicom, &warnings)) << error;
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(DifferingVoxels(back->GetImageData(), knee.Labels.Image), 0u);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(back->GetIJKToRASMatrix()->GetElement(r, c), knee.Labels.IJKToRAS->GetElement(r, c), 1e-4);
  ASSERT_EQ(back->GetNumberOfSegments(), 3);
  for (int n = 0; n < 3; ++n) {
    const rp::Segment& a = knee.Node->GetNthSegment(n);
    const rp::Segment& b = back->GetNthSegment(n);
    EXPECT_EQ(b.ID, a.ID);
    EXPECT_EQ(b.Name, a.Name);
    EXPECT_EQ(b.LabelValue, a.LabelValue);
    EXPECT_EQ(b.TissueClass, "bone");
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.Color[c], a.Color[c], 2e-3) << b.ID;  // CIELab rounding
  }

  // Read back alone (no referenced series): the grid its frames span, same voxels there.
  vtkNew<vtkRPSegmentationNode> alone;
  ASSERT_TRUE(rp::ReadDicomSegmentation(dir.string(), alone, error)) << error;  // the folder's only SEG
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(knee.Labels.IJKToRAS, rasToIJK);
  const double origin[4] = {alone->GetIJKToRASMatrix()->GetElement(0, 3), alone->GetIJKToRASMatrix()->GetElement(1, 3),
                            alone->GetIJKToRASMatrix()->GetElement(2, 3), 1};
  double shift[4];
  rasToIJK->MultiplyPoint(origin, shift);
  int dims[3], full[3];
  alone->GetImageData()->GetDimensions(dims);
  knee.Labels.Image->GetDimensions(full);
  EXPECT_NEAR(shift[0], 0, 1e-4);
  EXPECT_NEAR(shift[1], 0, 1e-4);
  const int k0 = static_cast<int>(std::lround(shift[2]));
  ASSERT_NEAR(shift[2], k0, 1e-4);
  const std::map<int, size_t> counts = CountLabels(knee.Labels.Image);
  std::map<int, size_t> aloneCounts = CountLabels(alone->GetImageData());
  for (int l = 1; l <= 3; ++l) EXPECT_EQ(aloneCounts[l], counts.at(l)) << l;
  size_t differing = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        differing += alone->GetImageData()->GetScalarComponentAsDouble(i, j, k, 0) !=
                     knee.Labels.Image->GetScalarComponentAsDouble(i, j, k + k0, 0);
  EXPECT_EQ(differing, 0u);

  // The one loader (what `mesh`, `convert` and the viewer open paths with) reads it as a segmentation.
  ASSERT_TRUE(rp::RegisterImagingReaders());
  vtkNew<vtkRPScene> scene;
  rp::LoadResult load = rp::LoadPath(scene, seg.string());
  ASSERT_TRUE(load.Ok) << load.Error;
  EXPECT_EQ(load.Reader, "DICOM SEG / RTSTRUCT");
  ASSERT_EQ(load.Nodes.size(), 1u);
  auto* loaded = vtkRPSegmentationNode::SafeDownCast(load.Nodes[0]);
  ASSERT_NE(loaded, nullptr);
  EXPECT_EQ(loaded->GetNumberOfSegments(), 3);

  // DCMTK's own dump parses it.
  const std::string dcmdump = rp::testing::FindTool("dcmdump");
  if (!dcmdump.empty()) {
    EXPECT_EQ(rp::testing::RunTool(dcmdump, {"-q", seg.string()}, (dir / "dcmdump.log").string()), 0);
  }
  const std::string dciodvfy = rp::testing::FindTool("dciodvfy");
  if (!dciodvfy.empty()) {  // David Clunie's IOD verifier (dicom3tools): no error against the SEG IOD
    rp::testing::RunTool(dciodvfy, {seg.string()}, (dir / "dciodvfy.log").string());
    std::istringstream log(Slurp(dir / "dciodvfy.log"));
    for (std::string line; std::getline(log, line);) EXPECT_NE(line.rfind("Error", 0), 0u) << line;
  }

  // pydicom, an independent reader: what a PACS sees.
  if (!HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed: the independent reader check is skipped";
  ASSERT_EQ(RunPython(CheckSegScript, dir, {seg.string()}), 0) << Slurp(dir / "python.log");
  const nlohmann::json seen = nlohmann::json::parse(Slurp(dir / "python.out"));
  rp::DicomScanResult scan;
  ASSERT_TRUE(rp::ScanDicom(knee.Dicom, scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(seen["sopClass"], "1.2.840.10008.5.1.4.1.1.66.4");
  EXPECT_EQ(seen["modality"], "SEG");
  EXPECT_EQ(seen["type"], "BINARY");
  EXPECT_EQ(seen["bitsAllocated"], 1);
  EXPECT_EQ(seen["referencedSeries"], scan.Series[0].SeriesInstanceUID);
  EXPECT_EQ(seen["studyUID"], scan.Series[0].StudyInstanceUID);
  EXPECT_EQ(seen["referencedInstances"], 150);
  EXPECT_EQ(seen["derivedFrom"], seen["frames"]);
  ASSERT_EQ(seen["segments"].size(), 3u);
  EXPECT_EQ(seen["segments"][0]["label"], "Tibia");
  EXPECT_EQ(seen["segments"][0]["type"], "Tibia");
  EXPECT_EQ(seen["segments"][2]["type"], "Patella");
  size_t frames = 0;
  for (int l = 1; l <= 3; ++l) {
    EXPECT_EQ(seen["voxels"][std::to_string(l)].get<size_t>(), counts.at(l)) << l;
    // Every frame at a CT slice position (z = 350 ... 499 mm LPS, 1 mm apart).
    for (double z : seen["z"][std::to_string(l)]) {
      EXPECT_NEAR(z, std::round(z), 1e-6);
      EXPECT_GE(z, 350.0);
      EXPECT_LE(z, 499.0);
    }
    frames += seen["z"][std::to_string(l)].size();
  }
  EXPECT_EQ(seen["frames"].get<size_t>(), frames);
  std::cout << "SEG round trip: " << frames << " frames, " << counts.at(1) + counts.at(2) + counts.at(3)
            << " labelled voxels, 0 differing\n";
}

TEST(DicomSegmentation, FractionalSegFromPydicomReadsThresholdedAtHalf) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  if (!HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed";
  Knee knee;
  ASSERT_NO_FATAL_FAILURE(LoadKnee(knee));
  const fs::path dir = rp::testing::Scratch("seg-fractional");
  std::string error;
  ASSERT_TRUE(rp::WriteDicomSegmentation(knee.Node, knee.Dicom, (dir / "binary.dcm").string(), error)) << error;
  const fs::path fractional = dir / "fractional" / "seg.dcm";
  fs::create_directories(fractional.parent_path());
  ASSERT_EQ(RunPython(FractionalScript, dir, {(dir / "binary.dcm").string(), fractional.string()}), 0) << Slurp(dir / "python.log");
  vtkNew<vtkRPSegmentationNode> back;
  std::vector<std::string> warnings;
  ASSERT_TRUE(rp::ReadDicomSegmentation(fractional.string(), back, error, knee.Dicom, &warnings)) << error;
  EXPECT_EQ(DifferingVoxels(back->GetImageData(), knee.Labels.Image), 0u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("fractional SEG"), std::string::npos) << warnings[0];
}

TEST(DicomSegmentation, SegOnAnotherSeriesIsRefusedNamingTheFrame) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  RP_REQUIRE_SHARED_DATA("dicom/ct-3slice");
  Knee knee;
  ASSERT_NO_FATAL_FAILURE(LoadKnee(knee));
  const fs::path dir = rp::testing::Scratch("seg-mismatch");
  std::string error;
  const fs::path seg = dir / "seg.dcm";
  ASSERT_TRUE(rp::WriteDicomSegmentation(knee.Node, knee.Dicom, seg.string(), error)) << error;
  vtkNew<vtkRPSegmentationNode> back;
  EXPECT_FALSE(rp::ReadDicomSegmentation(seg.string(), back, error, rptest::SharedDataPath("dicom/ct-3slice")));
  EXPECT_TRUE(error.find("frames of 146x176 pixels, the referenced series' images 512x512") != std::string::npos ||
              error.find("Frame of Reference") != std::string::npos)
      << error;
  EXPECT_EQ(back->GetNumberOfSegments(), 0);  // nothing half-loaded
  // Writing against a series of another grid is refused too.
  EXPECT_FALSE(rp::WriteDicomSegmentation(knee.Node, rptest::SharedDataPath("dicom/ct-3slice"), (dir / "x.dcm").string(), error));
  EXPECT_NE(error.find("is not the referenced series' grid"), std::string::npos) << error;
  // An RTSTRUCT path is not a SEG.
  EXPECT_FALSE(rp::ReadDicomSegmentation(knee.Dicom, back, error));
  EXPECT_NE(error.find("holds no) DICOM Segmentation"), std::string::npos) << error;
}

namespace {

double DistanceToSegment(const double p[2], const double a[2], const double b[2]) {
  const double d[2] = {b[0] - a[0], b[1] - a[1]};
  const double length2 = d[0] * d[0] + d[1] * d[1];
  const double t = length2 > 0 ? std::clamp(((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / length2, 0.0, 1.0) : 0.0;
  return std::hypot(p[0] - a[0] - t * d[0], p[1] - a[1] - t * d[1]);
}

}  // namespace

TEST(DicomSegmentation, KneeRtStructFromPydicomRasterizesWithinHalfAVoxel) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  if (!HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed";
  Knee knee;
  ASSERT_NO_FATAL_FAILURE(LoadKnee(knee));
  const fs::path dir = rp::testing::Scratch("rtstruct-knee");
  int dims[3];
  knee.Labels.Image->GetDimensions(dims);
  // Contours per label and slice, in voxel units too (for the distance check below).
  nlohmann::json spec = {{"rois", nlohmann::json::array()}};
  std::map<std::pair<int, int>, std::vector<std::vector<double>>> ijkContours;  // (label, k) → i, j pairs
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(knee.Labels.IJKToRAS, rasToIJK);
  for (int l = 1; l <= 3; ++l) {
    const rp::Segment& s = knee.Node->GetNthSegment(l - 1);
    nlohmann::json roi = {{"name", s.Name}, {"contours", nlohmann::json::array()},
                          {"color", {int(s.Color[0] * 255), int(s.Color[1] * 255), int(s.Color[2] * 255)}}};
    for (int k = 0; k < dims[2]; ++k)
      for (const auto& contour : SliceContours(knee.Labels.Image, knee.Labels.IJKToRAS, l, k)) {
        roi["contours"].push_back(contour);
        std::vector<double> ij;
        for (size_t p = 0; p < contour.size(); p += 3) {
          const double ras[4] = {-contour[p], -contour[p + 1], contour[p + 2], 1};
          double ijk[4];
          rasToIJK->MultiplyPoint(ras, ijk);
          ij.insert(ij.end(), {ijk[0], ijk[1]});
        }
        ijkContours[{l, k}].push_back(ij);
      }
    spec["rois"].push_back(roi);
  }
  // One stray contour 0.5 mm between two slices: left out with a warning naming its ROI.
  spec["rois"][2]["contours"].push_back({-120, -200, 400.5, -110, -200, 400.5, -110, -190, 400.5});
  std::ofstream(dir / "contours.json") << spec.dump();
  const fs::path rtstruct = dir / "rt" / "rtstruct.dcm";
  fs::create_directories(rtstruct.parent_path());
  ASSERT_EQ(RunPython(RtStructScript, dir, {(dir / "contours.json").string(), knee.Dicom, rtstruct.string()}), 0)
      << Slurp(dir / "python.log");

  vtkNew<vtkRPSegmentationNode> back;
  std::vector<std::string> warnings;
  std::string error;
  ASSERT_TRUE(rp::ReadDicomRtStruct(rtstruct.string(), back, error, knee.Dicom, &warnings)) << error;
  std::string all;
  for (const auto& w : warnings) all += w + "\n";
  ASSERT_EQ(warnings.size(), 1u) << all;
  EXPECT_NE(warnings[0].find("ROI 'Patella': 1 contour(s) on no slice"), std::string::npos) << warnings[0];
  ASSERT_EQ(back->GetNumberOfSegments(), 3);
  EXPECT_EQ(back->GetNthSegment(0).Name, "Tibia");
  EXPECT_NEAR(back->GetNthSegment(1).Color[2], int(0.9 * 255) / 255.0, 1e-9);
  EXPECT_EQ(back->GetName(), std::string("knee bones"));
  {  // The loader, given a folder holding the CT and the RTSTRUCT: both, the RTSTRUCT on the CT's
     // grid and referencing it.
    ASSERT_TRUE(rp::RegisterImagingReaders());
    const fs::path folder = dir / "ct-and-rtstruct";
    fs::copy(knee.Dicom, folder, fs::copy_options::recursive);
    fs::copy_file(rtstruct, folder / "rtstruct.dcm");
    vtkNew<vtkRPScene> scene;
    rp::LoadResult load = rp::LoadPath(scene, folder.string());
    ASSERT_TRUE(load.Ok) << load.Error;
    EXPECT_EQ(load.Reader, "DICOM");
    ASSERT_EQ(load.Nodes.size(), 2u);
    auto* loaded = vtkRPSegmentationNode::SafeDownCast(load.Nodes[1]);
    ASSERT_NE(loaded, nullptr);
    EXPECT_EQ(DifferingVoxels(loaded->GetImageData(), back->GetImageData()), 0u);
    EXPECT_EQ(loaded->GetNodeReference(vtkRPSegmentationNode::ReferenceImageGeometryRole()), load.Nodes[0].GetPointer());
  }
  // Dice per bone, and every differing voxel's centre within half a voxel of the contour.
  for (int l = 1; l <= 3; ++l) {
    size_t both = 0, truth = 0, read = 0, differing = 0;
    double worst = 0.0;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const bool a = knee.Labels.Image->GetScalarComponentAsDouble(i, j, k, 0) == l;
          const bool b = back->GetImageData()->GetScalarComponentAsDouble(i, j, k, 0) == l;
          both += a && b;
          truth += a;
          read += b;
          if (a == b) continue;
          ++differing;
          double nearest = 1e9;
          const double p[2] = {double(i), double(j)};
          for (const auto& ij : ijkContours[{l, k}])
            for (size_t q = 0; q < ij.size(); q += 2) {
              const size_t r = (q + 2) % ij.size();
              nearest = std::min(nearest, DistanceToSegment(p, &ij[q], &ij[r]));
            }
          worst = std::max(worst, nearest);
        }
    const double dice = 2.0 * both / double(truth + read);
    std::cout << back->GetNthSegment(l - 1).Name << ": Dice " << dice << ", " << differing
              << " differing voxel(s), farthest " << worst << " voxel from the contour\n";
    EXPECT_GT(dice, 0.995) << l;
    EXPECT_LE(worst, 0.5 + 1e-6) << l;
  }
}

// SEG and RTSTRUCT in Deflated Explicit VR Little Endian read as their images do (issue 39): the
// knee's SEG (ours) and RTSTRUCT (pydicom's) deflated by DCMTK (dcmconv +td), GDCM (gdcmconv
// --deflated) and pydicom, each checked by pydicom to be deflated and to hold the same segments,
// read back voxel-identical to the same object in Explicit VR Little Endian, alone and in a
// folder whose CT is deflated too.
TEST(DicomSegmentation, DeflatedSegAndRtStructReadAsTheirImagesDo) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  if (!HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed";
  Knee knee;
  ASSERT_NO_FATAL_FAILURE(LoadKnee(knee));
  const fs::path dir = rp::testing::Scratch("deflated");
  std::string error;
  const fs::path seg = dir / "seg.dcm", rtstruct = dir / "rtstruct.dcm";
  ASSERT_TRUE(rp::WriteDicomSegmentation(knee.Node, knee.Dicom, seg.string(), error)) << error;
  nlohmann::json spec = {{"rois", nlohmann::json::array()}};
  int dims[3];
  knee.Labels.Image->GetDimensions(dims);
  for (int l = 1; l <= 3; ++l) {
    nlohmann::json roi = {{"name", knee.Node->GetNthSegment(l - 1).Name}, {"color", {200, 100, 50}},
                          {"contours", nlohmann::json::array()}};
    for (int k = 0; k < dims[2]; ++k)
      for (const auto& contour : SliceContours(knee.Labels.Image, knee.Labels.IJKToRAS, l, k)) roi["contours"].push_back(contour);
    spec["rois"].push_back(roi);
  }
  std::ofstream(dir / "contours.json") << spec.dump();
  ASSERT_EQ(RunPython(RtStructScript, dir, {(dir / "contours.json").string(), knee.Dicom, rtstruct.string()}), 0)
      << Slurp(dir / "python.log");
  vtkNew<vtkRPSegmentationNode> plainRt;
  ASSERT_TRUE(rp::ReadDicomRtStruct(rtstruct.string(), plainRt, error, knee.Dicom)) << error;

  // Every writer's deflated copy of each.
  std::vector<std::pair<std::string, std::string>> encoders;  // name, command prefix ("" = pydicom)
  for (const auto& [tool, arguments] : {std::make_pair("dcmconv", "+td"), std::make_pair("gdcmconv", "--deflated")}) {
    const std::string path = rp::testing::FindTool(tool);
    if (!path.empty()) encoders.emplace_back(tool, path + " " + arguments);
  }
  encoders.emplace_back("pydicom", "");
  for (const auto& [name, command] : encoders) {
    for (const fs::path& source : {seg, rtstruct}) {
      const fs::path deflated = dir / (name + "-" + source.filename().string());
      if (command.empty()) {
        ASSERT_EQ(RunPython(DeflateScript, dir, {source.string(), deflated.string()}), 0) << Slurp(dir / "python.log");
      } else {
        ASSERT_EQ(std::system((command + " '" + source.string() + "' '" + deflated.string() + "'").c_str()), 0) << name;
      }
      ASSERT_EQ(RunPython(DeflateScript, dir, {deflated.string(), (dir / "check.dcm").string()}), 0)
          << Slurp(dir / "python.log");  // pydicom reads it (and deflates it again)
      vtkNew<vtkRPSegmentationNode> back;
      std::vector<std::string> warnings;
      if (source == seg) {
        ASSERT_TRUE(rp::ReadDicomSegmentation(deflated.string(), back, error, knee.Dicom, &warnings)) << name << ": " << error;
        EXPECT_EQ(DifferingVoxels(back->GetImageData(), knee.Labels.Image), 0u) << name;
        ASSERT_EQ(RunPython(CheckSegScript, dir, {deflated.string()}), 0) << Slurp(dir / "python.log");
        const nlohmann::json seen = nlohmann::json::parse(Slurp(dir / "python.out"));
        EXPECT_EQ(seen["segments"].size(), 3u) << name;
      } else {
        ASSERT_TRUE(rp::ReadDicomRtStruct(deflated.string(), back, error, knee.Dicom, &warnings)) << name << ": " << error;
        EXPECT_EQ(DifferingVoxels(back->GetImageData(), plainRt->GetImageData()), 0u) << name;
      }
      EXPECT_EQ(back->GetNumberOfSegments(), 3) << name;
      std::ifstream in(deflated, std::ios::binary);
      const std::string head((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(head.find("1.2.840.10008.1.2.1.99"), std::string::npos) << name << " did not deflate";
    }
  }
  // A deflated study: the CT, the SEG and the RTSTRUCT deflated by DCMTK, opened whole.
  const std::string dcmconv = rp::testing::FindTool("dcmconv");
  if (dcmconv.empty()) return;
  const fs::path folder = dir / "study";
  fs::create_directories(folder);
  for (const auto& entry : fs::directory_iterator(knee.Dicom))
    ASSERT_EQ(std::system((dcmconv + " +td '" + entry.path().string() + "' '" + (folder / entry.path().filename()).string() + "'").c_str()), 0);
  fs::copy_file(dir / "dcmconv-seg.dcm", folder / "seg.dcm");
  fs::copy_file(dir / "dcmconv-rtstruct.dcm", folder / "rtstruct.dcm");
  ASSERT_TRUE(rp::RegisterImagingReaders());
  vtkNew<vtkRPScene> scene;
  const rp::LoadResult load = rp::LoadPath(scene, folder.string());
  ASSERT_TRUE(load.Ok) << load.Error;
  ASSERT_EQ(load.Nodes.size(), 3u);
  for (size_t n = 1; n < 3; ++n) {
    auto* segmentation = vtkRPSegmentationNode::SafeDownCast(load.Nodes[n]);
    ASSERT_NE(segmentation, nullptr);
    EXPECT_EQ(segmentation->GetNodeReference(vtkRPSegmentationNode::ReferenceImageGeometryRole()), load.Nodes[0].GetPointer());
    EXPECT_EQ(DifferingVoxels(segmentation->GetImageData(),
                              segmentation->GetName() == "knee bones" ? plainRt->GetImageData() : knee.Labels.Image.GetPointer()),
              0u)
        << segmentation->GetName();
  }
}
