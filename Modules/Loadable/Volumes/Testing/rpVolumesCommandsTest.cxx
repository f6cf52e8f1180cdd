// The Volumes CLI end to end (phantom → DICOM listing → conversion → registration with a known
// answer) and the scene logic (load, register into a transform node, failures change nothing).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpKneePhantom.h"
#include "rpImagingReaders.h"
#include "rpKneeStudy.h"
#include "rpSceneIO.h"
#include "rpSegmentationIO.h"
#include "rpSharedData.h"
#include "rpTransformIO.h"
#include "rpVolumeFiles.h"
#include "rpVolumeRegistration.h"
#include "rpVolumesCommands.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPVolumesLogic.h"

namespace fs = std::filesystem;

namespace {

struct CommandRun {
  int code;
  std::string out, err;
  nlohmann::json Json() const { return nlohmann::json::parse(out); }
};

// A command run as `roboplan` runs it, after the Volumes module's Setup registered the imaging
// readers (VolumesModule.cxx; this test calls the commands without the module).
CommandRun Call(int (*command)(const std::vector<std::string>&, std::ostream&, std::ostream&), std::vector<std::string> args) {
  rp::RegisterImagingReaders();
  std::ostringstream out, err;
  const int code = command(args, out, err);
  return {code, out.str(), err.str()};
}

const fs::path& Dir() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(ROBOPLAN_TEST_OUTPUT_DIR);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// The phantom written once for all tests.
const fs::path& PhantomDir() {
  static const fs::path dir = [] {
    const fs::path d = Dir() / "phantom";
    const CommandRun r = Call(rp::RunPhantomCommand, {"--out", d.string(), "--size", "small", "--json"});
    EXPECT_EQ(r.code, 0) << r.err;
    return d;
  }();
  return dir;
}

bool SameVoxels(const rp::ImageVolume& a, const rp::ImageVolume& b) {
  vtkDataArray* sa = a.Image->GetPointData()->GetScalars();
  vtkDataArray* sb = b.Image->GetPointData()->GetScalars();
  if (sa->GetNumberOfTuples() != sb->GetNumberOfTuples()) return false;
  for (vtkIdType i = 0; i < sa->GetNumberOfTuples(); ++i)
    if (sa->GetComponent(i, 0) != sb->GetComponent(i, 0)) return false;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a.IJKToRAS->GetElement(r, c) - b.IJKToRAS->GetElement(r, c)) > 1e-5) return false;
  return true;
}

}  // namespace

// `roboplan dicom` shows what the reader will assume (an invalid PixelSpacing read as 1 mm), as
// text and in --json; `roboplan convert` turns a .seg.nrrd into a DICOM SEG on the CT's grid
// (--reference) and back, voxel for voxel.
TEST(VolumesCommands, DicomWarnsOfInvalidSpacingAndConvertConvertsSegmentations) {
  const fs::path dir = PhantomDir();
  const fs::path zero = Dir() / "zero-spacing";
  fs::remove_all(zero);
  fs::copy(dir / "CT", zero, fs::copy_options::recursive);
  const std::string modify = "dcmodify -nb -m \"(0028,0030)=0\\\\0\" \"" + zero.string() + "\"/*.dcm >/dev/null 2>&1";
  if (std::system("dcmodify --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "dcmodify (dcmtk) not installed";
  ASSERT_EQ(std::system(modify.c_str()), 0);
  CommandRun r = Call(rp::RunDicomCommand, {zero.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: PixelSpacing 0\\0 in "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1.000 x 1.000"), std::string::npos) << r.out;
  r = Call(rp::RunDicomCommand, {zero.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto warnings = r.Json()["series"][0]["warnings"];
  ASSERT_EQ(warnings.size(), 1u) << r.out;
  EXPECT_NE(warnings[0].get<std::string>().find("1 mm pixels assumed"), std::string::npos) << r.out;

  // labels.nrrd (on the CT's grid) as a segmentation file, then SEG and back.
  rp::ImageVolume labels;
  std::string error;
  ASSERT_TRUE(rp::ReadVolume((dir / "labels.nrrd").string(), labels, error)) << error;
  vtkNew<vtkRPSegmentationNode> node;
  rp::CopyToNode(labels, node.GetPointer());
  double range[2];
  labels.Image->GetScalarRange(range);
  for (int l = 1; l <= static_cast<int>(range[1]); ++l) {
    rp::Segment s;
    s.ID = "label" + std::to_string(l);
    s.Name = "Label " + std::to_string(l);
    s.LabelValue = l;
    node->SetSegment(s);
  }
  const fs::path segNrrd = Dir() / "labels.seg.nrrd", segDicom = Dir() / "labels-seg.dcm", back = Dir() / "back.seg.nrrd";
  ASSERT_TRUE(rp::WriteSegmentationFile(segNrrd.string(), node, error)) << error;
  r = Call(rp::RunConvertCommand, {segNrrd.string(), segDicom.string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--reference"), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {segNrrd.string(), segDicom.string(), "--reference", (dir / "CT").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  r = Call(rp::RunConvertCommand, {segDicom.string(), back.string(), "--reference", (dir / "CT").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.Json()["segments"], node->GetNumberOfSegments());
  vtkNew<vtkRPSegmentationNode> read;
  ASSERT_TRUE(rp::ReadSegmentationFile(back.string(), read, error)) << error;
  EXPECT_TRUE(SameVoxels(labels, rp::FromNode(read))) << "SEG round trip through roboplan convert";
  ASSERT_EQ(read->GetNumberOfSegments(), node->GetNumberOfSegments());
  EXPECT_EQ(read->GetNthSegment(0).Name, "Label 1");
}

// A labelmap becomes a segmentation and a DICOM SEG in two commands, and comes back: labels.nrrd
// (knee-ct-vhf, a plain labelmap) with a Slicer colour table → .seg.nrrd → SEG on the CT → .seg.nrrd:
// identical voxels, names and colours (as 8-bit, the colour table's precision), the tissue class
// the names give; pydicom (an independent reader) sees the SEG's segments and voxels.
TEST(VolumesCommands, LabelmapToSegmentationToDicomSegAndBack) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  const fs::path dir = Dir() / "labelmap-seg";
  rp::testing::KneeStudy study;
  std::string error;
  if (!rp::testing::HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed";
  ASSERT_TRUE(rp::testing::MakeKneeStudy(dir, study, error)) << error;  // the two commands, among others
  rp::ImageVolume labels;
  ASSERT_TRUE(rp::ReadVolume(study.Labels.string(), labels, error)) << error;
  auto checkSegments = [](vtkRPSegmentationNode* node, const std::string& what) {
    ASSERT_EQ(node->GetNumberOfSegments(), 3) << what;
    for (int s = 0; s < 3; ++s) {
      const auto& segment = node->GetNthSegment(s);
      const auto& expected = rp::testing::KneeLabels()[static_cast<size_t>(s)];
      EXPECT_EQ(segment.Name, expected.Name) << what;
      EXPECT_EQ(segment.LabelValue, s + 1) << what;
      EXPECT_EQ(segment.TissueClass, "bone") << what;  // the names are bones
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(std::lround(255 * segment.Color[c]), expected.Color[static_cast<size_t>(c)]) << what << " " << s;
    }
  };
  vtkNew<vtkRPSegmentationNode> first;
  ASSERT_TRUE(rp::ReadSegmentationFile(study.SegNrrd.string(), first, error)) << error;
  EXPECT_TRUE(SameVoxels(labels, rp::FromNode(first)));
  checkSegments(first, "labelmap → .seg.nrrd");
  // The SEG back to a .seg.nrrd (on the CT's grid: the folder's series), and through pydicom.
  const fs::path back = dir / "back.seg.nrrd";
  CommandRun r = Call(rp::RunConvertCommand, {study.Seg.string(), back.string(), "--reference", study.CtFolder.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  vtkNew<vtkRPSegmentationNode> second;
  ASSERT_TRUE(rp::ReadSegmentationFile(back.string(), second, error)) << error;
  EXPECT_TRUE(SameVoxels(labels, rp::FromNode(second))) << "labelmap → .seg.nrrd → SEG → .seg.nrrd";
  checkSegments(second, "→ SEG → .seg.nrrd");
  ASSERT_EQ(rp::testing::RunPython(rp::testing::CheckSegScript, dir, {study.Seg.string()}), 0)
      << rp::testing::Slurp(dir / "python.log");
  const nlohmann::json seen = nlohmann::json::parse(rp::testing::Slurp(dir / "python.out"));
  ASSERT_EQ(seen["segments"].size(), 3u);
  std::map<int, size_t> counts;
  vtkDataArray* voxels = labels.Image->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < voxels->GetNumberOfTuples(); ++i) ++counts[static_cast<int>(voxels->GetComponent(i, 0))];
  for (int s = 0; s < 3; ++s) {
    EXPECT_EQ(seen["segments"][s]["label"], rp::testing::KneeLabels()[static_cast<size_t>(s)].Name);
    EXPECT_EQ(seen["voxels"][std::to_string(s + 1)].get<size_t>(), counts[s + 1]) << s;
  }
  // Without a table: "Label N"; an image is not a labelmap; a plain labelmap named *.seg.nrrd
  // (as earlier versions of convert wrote one) is one.
  r = Call(rp::RunConvertCommand, {study.Labels.string(), (dir / "plain.seg.nrrd").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.Json()["segmentNames"], nlohmann::json({"Label 1", "Label 2", "Label 3"}));
  EXPECT_EQ(r.Json()["inputKind"], "labelmap");
  r = Call(rp::RunConvertCommand, {study.CtFolder.string(), (dir / "ct.seg.nrrd").string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is an intensity image"), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {study.Labels.string(), (dir / "x.seg.nrrd").string(), "--input-kind", "intensity"});
  EXPECT_EQ(r.code, 2);
  fs::copy_file(study.Labels, dir / "old-plain.seg.nrrd");
  r = Call(rp::RunConvertCommand, {(dir / "old-plain.seg.nrrd").string(), (dir / "new.seg.nrrd").string(), "--labels",
                                   study.SegNrrd.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  vtkNew<vtkRPSegmentationNode> relabelled;  // names and colours from the other .seg.nrrd
  ASSERT_TRUE(rp::ReadSegmentationFile((dir / "new.seg.nrrd").string(), relabelled, error)) << error;
  checkSegments(relabelled, "--labels a .seg.nrrd");
}

// A study folder (CT + SEG + RTSTRUCT): `dicom` lists the segmentations with the series they lie
// on; `convert <folder> <volume>` takes the CT; `convert <folder> <x.seg.nrrd>` names the two
// segmentations and takes the one --series names, on the CT's grid.
TEST(VolumesCommands, StudyFolderListsAndConvertsEachObject) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  if (!rp::testing::HavePydicom()) GTEST_SKIP() << "pydicom (python3-pydicom) not installed";
  const fs::path dir = Dir() / "study";
  rp::testing::KneeStudy study;
  std::string error;
  ASSERT_TRUE(rp::testing::MakeKneeStudy(dir, study, error)) << error;
  CommandRun r = Call(rp::RunDicomCommand, {study.Folder.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json listing = r.Json();
  ASSERT_EQ(listing["series"].size(), 1u);
  ASSERT_EQ(listing["segmentations"].size(), 2u);
  EXPECT_EQ(listing["nonImageDicomFiles"], 0);
  const std::string ct = listing["series"][0]["seriesInstanceUID"];
  std::set<std::string> kinds;
  std::string segID;
  for (const auto& o : listing["segmentations"]) {
    kinds.insert(o["kind"].get<std::string>());
    EXPECT_EQ(o["referencedSeriesInstanceUID"], ct);
    EXPECT_TRUE(o["referencedSeriesPresent"].get<bool>());
    EXPECT_EQ(o["segments"], nlohmann::json({"Tibia", "Fibula", "Patella"}));
    if (o["kind"] == "SEG") segID = o["id"];
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"SEG", "RTSTRUCT"}));
  r = Call(rp::RunDicomCommand, {study.Folder.string()});
  EXPECT_NE(r.out.find("1 series and 2 segmentation object(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("on " + ct + " (CT"), std::string::npos) << r.out;

  r = Call(rp::RunConvertCommand, {study.Folder.string(), (dir / "ct.nrrd").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  rp::ImageVolume fromFolder, fromCt;
  ASSERT_TRUE(rp::ReadVolume((dir / "ct.nrrd").string(), fromFolder, error)) << error;
  ASSERT_TRUE(rp::ReadVolume(study.CtFolder.string(), fromCt, error)) << error;
  EXPECT_TRUE(SameVoxels(fromFolder, fromCt));

  r = Call(rp::RunConvertCommand, {study.Folder.string(), (dir / "both.seg.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("holds 2 segmentations"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(segID), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {study.Folder.string(), (dir / "seg.seg.nrrd").string(), "--series", segID});
  ASSERT_EQ(r.code, 0) << r.err;
  vtkNew<vtkRPSegmentationNode> seg;
  ASSERT_TRUE(rp::ReadSegmentationFile((dir / "seg.seg.nrrd").string(), seg, error)) << error;
  rp::ImageVolume labels;
  ASSERT_TRUE(rp::ReadVolume(study.Labels.string(), labels, error)) << error;
  EXPECT_TRUE(SameVoxels(labels, rp::FromNode(seg))) << "the SEG on the CT's grid, from the folder";
  // The volumes logic takes the folder's one volume.
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  EXPECT_NE(logic->LoadVolume(study.Folder.string(), "", error), nullptr) << error;
}

TEST(VolumesCommands, PhantomDicomListingAndConversion) {
  const fs::path dir = PhantomDir();
  for (const char* f : {"CT", "MR", "labels.nrrd", "MRToCT-truth.tfm", "phantom.json"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
  const nlohmann::json info = nlohmann::json::parse(std::ifstream(dir / "phantom.json"));
  EXPECT_EQ(info["tissues"].size(), static_cast<size_t>(rp::KneeLabelCount));
  EXPECT_EQ(info["ct"]["dimensions"], nlohmann::json({110, 110, 64}));

  CommandRun r = Call(rp::RunDicomCommand, {dir.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = r.Json();
  ASSERT_EQ(doc["series"].size(), 2u);  // CT and MR, found recursively
  std::set<std::string> modalities;
  for (const auto& s : doc["series"]) {
    modalities.insert(s["modality"].get<std::string>());
    EXPECT_TRUE(s["loadable"].get<bool>()) << s["problem"];
    if (s["modality"] == "MR") {
      EXPECT_NEAR(s["spacing"][2].get<double>(), 1.7, 1e-6);
      EXPECT_EQ(s["size"], nlohmann::json({96, 96, 84}));
    }
  }
  EXPECT_EQ(modalities, (std::set<std::string>{"CT", "MR"}));
  // labels.nrrd, the .tfm, phantom.json and the true surfaces of the real knee.
  EXPECT_EQ(info["surfaces"].size(), 11u);
  EXPECT_EQ(doc["nonDicomFiles"], 3 + info["surfaces"].size());

  // DICOM → NRRD → DICOM → NIfTI: the same voxels and geometry as the generator's CT.
  rp::KneePhantomOptions options;
  options.GenerateMR = false;
  options.GenerateLabels = false;
  rp::KneePhantom phantom;
  std::string error;
  ASSERT_TRUE(rp::GenerateKneePhantom(options, phantom, error));
  ASSERT_EQ(Call(rp::RunConvertCommand, {(dir / "CT").string(), (Dir() / "ct.nrrd").string()}).code, 0);
  ASSERT_EQ(Call(rp::RunConvertCommand, {(Dir() / "ct.nrrd").string(), (Dir() / "ct-dicom").string()}).code, 0);
  r = Call(rp::RunConvertCommand, {(Dir() / "ct-dicom").string(), (Dir() / "ct.nii.gz").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.Json()["dimensions"], nlohmann::json({110, 110, 64}));
  for (const char* name : {"ct.nrrd", "ct-dicom", "ct.nii.gz"}) {
    rp::ImageVolume back;
    ASSERT_TRUE(rp::ReadVolume((Dir() / name).string(), back, error)) << error;
    EXPECT_TRUE(SameVoxels(phantom.CT, back)) << name;
  }

  // Failures: exit 1 with the problem named; bad arguments: exit 2.
  r = Call(rp::RunDicomCommand, {(Dir() / "no-such-folder").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no such file or folder"), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {(dir / "labels.nrrd").string(), (Dir() / "x.nrrd").string(), "--modality", "PET"});
  EXPECT_EQ(r.code, 2);
  r = Call(rp::RunPhantomCommand, {"--out", (Dir() / "p").string(), "--size", "huge"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--size"), std::string::npos);
  r = Call(rp::RunConvertCommand, {(Dir() / "missing.nrrd").string(), (Dir() / "y.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.nrrd"), std::string::npos) << r.err;
  // What a path is, the loader says (rp::FindDataReader): a model is refused as a model, by a
  // volume reader and by the segmentation-or-labelmap reader alike, not scanned as DICOM.
  const std::string model = (dir / "surfaces" / "femur.vtp").string();
  r = Call(rp::RunConvertCommand, {model, (Dir() / "z.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("is a model"), std::string::npos) << r.err;
  vtkNew<vtkRPSegmentationNode> segmentation;
  EXPECT_FALSE(rp::ReadSegmentationOrLabelmap(model, segmentation, error));
  EXPECT_NE(error.find("is a model"), std::string::npos) << error;
  ASSERT_TRUE(rp::ReadSegmentationOrLabelmap((dir / "labels.nrrd").string(), segmentation, error)) << error;
  EXPECT_GT(segmentation->GetNumberOfSegments(), 10);
}

// The real-data case as close as shared/data allows (no real JPEG 2000 knee MR there):
// four Pac-Man MR slices made oblique (IOP and IPP rotated 30 degrees about x by dcmodify) and
// JPEG 2000-compressed by gdcmconv, plus two slices of the same series relabelled sagittal (a
// localizer under the same UID). `roboplan dicom` lists two stacks; `convert` refuses the
// series as a whole, naming them, and converts the oblique stack with the headers' geometry.
TEST(VolumesCommands, ObliqueJpeg2000StackOfAMixedSeries) {
  RP_REQUIRE_SHARED_DATA("dicom/pacsman-mr");
  const fs::path source = rptest::SharedDataPath("dicom/pacsman-mr");
  for (const char* tool : {"dcmodify", "gdcmconv"})
    if (std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) != 0)
      GTEST_SKIP() << tool << " not found on PATH (Debian packages dcmtk, libgdcm-tools)";
  const fs::path dir = Dir() / "mixed-series", work = Dir() / "mixed-work";
  fs::remove_all(dir);
  fs::remove_all(work);
  fs::create_directories(dir);
  fs::create_directories(work);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  auto run = [&](const std::string& command) { return std::system((command + " >>" + (work / "log").string() + " 2>&1").c_str()); };
  auto ds = [](double v) {
    char t[32];
    std::snprintf(t, sizeof t, "%.10g", std::abs(v) < 1e-12 ? 0.0 : v);
    return std::string(t);
  };
  // Rotation about x by 30 degrees applied to IOP (0,-1,0 / 1,0,0) and IPP (-63, 0, z).
  const std::string iop = "0\\" + ds(-c) + "\\" + ds(-s) + "\\1\\0\\0";
  for (int k = 0; k < 4; ++k) {
    const std::string name = "slice" + std::to_string(50 + k) + ".dcm";
    fs::copy_file(source / name, work / name);
    const double z = 50 + k;
    const std::string ipp = "-63\\" + ds(-s * z) + "\\" + ds(c * z);
    ASSERT_EQ(run("dcmodify -nb -m '(0020,0037)=" + iop + "' -m '(0020,0032)=" + ipp + "' " + (work / name).string()), 0);
    ASSERT_EQ(run("gdcmconv --j2k " + (work / name).string() + " " + (dir / name).string()), 0);
  }
  for (int k = 0; k < 2; ++k) {
    const std::string name = "slice" + std::to_string(90 + k) + ".dcm";
    fs::copy_file(source / name, dir / name);
    ASSERT_EQ(run("dcmodify -nb -m '(0020,0037)=0\\1\\0\\0\\0\\-1' -m '(0020,0032)=" + std::to_string(4 * k) +
                  "\\-64\\64' " + (dir / name).string()), 0);
  }
  CommandRun r = Call(rp::RunDicomCommand, {dir.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto listing = r.Json()["series"];
  ASSERT_EQ(listing.size(), 2u);
  const std::string uid = listing[0]["seriesInstanceUID"];
  EXPECT_EQ(listing[0]["id"], uid + "#1");
  EXPECT_EQ(listing[0]["orientation"], "oblique axial (30.0°)");
  EXPECT_EQ(listing[0]["size"], nlohmann::json({128, 128, 4}));
  EXPECT_EQ(listing[0]["transferSyntax"], "JPEG 2000 Lossless Only (1.2.840.10008.1.2.4.90)");
  EXPECT_EQ(listing[1]["id"], uid + "#2");
  EXPECT_EQ(listing[1]["orientation"], "sagittal");
  r = Call(rp::RunDicomCommand, {dir.string()});
  EXPECT_NE(r.out.find(uid + "#1  (stack 1 of 2 in this series)"), std::string::npos) << r.out;

  r = Call(rp::RunConvertCommand, {dir.string(), (Dir() / "oblique.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("holds 2 stacks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("oblique axial (30.0°), 128x128x4"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sagittal, 128x128x2"), std::string::npos) << r.err;
  r = Call(rp::RunConvertCommand, {dir.string(), (Dir() / "oblique.nrrd").string(), "--series", uid + "#1", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  // From the tags: i along the row (0,-cos,-sin) LPS, j along the column (1,0,0), k along the
  // normal row x column = (0,-sin,cos), 1 mm; origin the IPP of slice50; RAS negates x and y.
  const double expected[3][4] = {{0, -1, 0, 63}, {c, 0, s, s * 50}, {-s, 0, c, c * 50}};
  rp::ImageVolume back;
  std::string error;
  ASSERT_TRUE(rp::ReadVolume((Dir() / "oblique.nrrd").string(), back, error)) << error;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) {
      EXPECT_NEAR(r.Json()["ijkToRAS"][row][col].get<double>(), expected[row][col], 1e-6) << row << "," << col;
      EXPECT_NEAR(back.IJKToRAS->GetElement(row, col), expected[row][col], 1e-6) << row << "," << col;
    }
}

// A header that promises 10^15 voxels: refused before allocating, naming the memory needed.
TEST(VolumesCommands, VolumeTooBigToFitIsRefused) {
  const fs::path path = Dir() / "too-big.nrrd";
  std::ofstream(path) << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 100000\n"
                         "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                         "space origin: (0,0,0)\nencoding: raw\n\n";
  const CommandRun r = Call(rp::RunConvertCommand, {path.string(), (Dir() / "out.nrrd").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("100000 x 100000 x 100000 voxels of 1 byte would need 1e+06 GB"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
}

TEST(VolumesCommands, RegisterVolumesRecoversTheTruth) {
  const fs::path dir = PhantomDir();
  const std::string out = (Dir() / "MRToCT.tfm").string();
  CommandRun r = Call(rp::RunRegisterVolumesCommand, {(dir / "CT").string(), (dir / "MR").string(), "--out", out, "--truth",
                                               (dir / "MRToCT-truth.tfm").string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const auto doc = r.Json();
  EXPECT_TRUE(doc["converged"].get<bool>());
  EXPECT_LT(doc["rmsToTruthMM"].get<double>(), 1.0);
  std::printf("[register-volumes] RMS to truth %.3f mm, %.2f s, %d iterations\n", doc["rmsToTruthMM"].get<double>(),
              doc["seconds"].get<double>(), doc["iterations"].get<int>());
  vtkNew<vtkMatrix4x4> written, truth;
  std::string error;
  ASSERT_TRUE(rp::ReadTransformFile(out, written, error)) << error;
  ASSERT_TRUE(rp::ReadTransformFile((dir / "MRToCT-truth.tfm").string(), truth, error)) << error;
  const std::vector<std::array<double, 3>> probe = {{0, 0, 0}, {40, 0, 0}, {0, 40, 0}, {0, 0, 40}};
  EXPECT_LT(rp::TransformRMSDifference(written, truth, probe), 1.0);

  // Not converged: exit 1, the file is not written.
  const std::string out2 = (Dir() / "unconverged.tfm").string();
  r = Call(rp::RunRegisterVolumesCommand,
           {(dir / "CT").string(), (dir / "MR").string(), "--out", out2, "--levels", "4", "--iterations", "2"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out2));
  r = Call(rp::RunRegisterVolumesCommand, {(dir / "CT").string(), (dir / "MR").string(), "--out", out2, "--levels", "0"});
  EXPECT_EQ(r.code, 2);
}

TEST(VolumesLogic, LoadAndRegisterIntoTheScene) {
  const fs::path dir = PhantomDir();
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPVolumesLogic> logic;
  logic->SetScene(scene);
  std::string error;
  vtkRPScalarVolumeNode* ct = logic->LoadVolume((dir / "CT").string(), "CT", error);
  ASSERT_NE(ct, nullptr) << error;
  vtkRPScalarVolumeNode* mr = logic->LoadVolume((dir / "MR").string(), "MR", error);
  ASSERT_NE(mr, nullptr) << error;
  EXPECT_DOUBLE_EQ(ct->GetWindow(), 2000.0);
  const int nodes = scene->GetNumberOfNodes();
  // A failed load changes nothing.
  EXPECT_EQ(logic->LoadVolume((dir / "labels.nrrd.missing").string(), "", error), nullptr);
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
  // Unconverged registration: nothing added, MR not moved.
  rp::RigidRegistrationOptions quick;
  quick.ShrinkFactors = {4};
  quick.SmoothingSigmasMM = {3.0};
  quick.MaxIterationsPerLevel = 2;
  rp::RigidRegistrationResult result;
  EXPECT_EQ(logic->RegisterVolumes(ct, mr, quick, result, error), nullptr);
  EXPECT_NE(error.find("did not converge"), std::string::npos);
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
  EXPECT_TRUE(mr->GetTransformNodeID().empty());

  rp::RigidRegistrationOptions options;  // defaults
  vtkRPLinearTransformNode* transform = logic->RegisterVolumes(ct, mr, options, result, error);
  ASSERT_NE(transform, nullptr) << error;
  EXPECT_EQ(transform->GetName(), "MRToCT");
  EXPECT_EQ(mr->GetTransformNodeID(), transform->GetID());
  vtkNew<vtkMatrix4x4> truth;
  ASSERT_TRUE(rp::ReadTransformFile((dir / "MRToCT-truth.tfm").string(), truth, error)) << error;
  vtkNew<vtkMatrix4x4> mrToWorld;
  mr->GetParentTransformToWorld(mrToWorld);
  // Bone-surface points of the knee, seen in MR coordinates, land where the CT has them.
  std::string loadError;
  const auto model = rp::LoadKneeSurfaceModel(loadError);
  ASSERT_TRUE(model) << loadError;
  const double bounds[6] = {-70, 70, -70, 70, -75, 75};
  const auto femur = model->SurfacePoints(rp::KneeStructure::Femur, 300, bounds);
  vtkNew<vtkMatrix4x4> ctToMR;
  vtkMatrix4x4::Invert(truth, ctToMR);
  std::vector<std::array<double, 3>> inMR;
  for (const auto& p : femur) {
    double q[4] = {p[0], p[1], p[2], 1.0};
    ctToMR->MultiplyPoint(q, q);
    inMR.push_back({q[0], q[1], q[2]});
  }
  EXPECT_LT(rp::TransformRMSDifference(mrToWorld, truth, inMR), 1.0);
}

// The logic calls `convert` makes for segmentations and scenes (no shared data): a labelmap of
// two boxes becomes a .seg.nrrd of two segments with the boxes' voxel counts; a volume-to-volume
// request is not a segmentation conversion; an intensity image is refused as a bad request (2);
// the segmentation's scene converts to Slicer's .mrml and back with its node.
TEST(VolumesLogic, ConvertsSegmentationsAndScenes) {
  const fs::path dir = Dir() / "logic-convert";
  fs::create_directories(dir);
  rp::ImageVolume labels;
  labels.Image = vtkSmartPointer<vtkImageData>::New();
  labels.Image->SetDimensions(20, 20, 10);
  labels.Image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(labels.Image->GetScalarPointer());
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) *v++ = (i < 5 && j < 4) ? 1 : (i >= 10 && k >= 5) ? 2 : 0;  // 4*5*10=200, 10*20*5=1000
  std::string error;
  ASSERT_TRUE(rp::WriteVolume((dir / "labels.nrrd").string(), labels, error)) << error;
  vtkNew<vtkRPVolumesLogic> logic;

  rp::SegmentationConversionRequest request;
  request.In = (dir / "labels.nrrd").string();
  request.Out = (dir / "labels.seg.nrrd").string();
  const rp::SegmentationConversion converted = logic->ConvertSegmentation(request);
  ASSERT_TRUE(converted.Applies);
  ASSERT_EQ(converted.FailureCode, 0) << converted.Error;
  EXPECT_EQ(converted.Segments, 2);
  EXPECT_EQ(converted.InputKind, "labelmap");
  vtkNew<vtkRPSegmentationNode> node;
  ASSERT_TRUE(rp::ReadSegmentationFile(request.Out, node, error)) << error;
  std::map<int, int> counts;
  const rp::ImageVolume back = rp::FromNode(node);
  vtkDataArray* voxels = back.Image->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < voxels->GetNumberOfTuples(); ++i) ++counts[static_cast<int>(voxels->GetComponent(i, 0))];
  EXPECT_EQ(counts[1], 200);
  EXPECT_EQ(counts[2], 1000);

  request.Out = (dir / "copy.nrrd").string();
  EXPECT_FALSE(logic->ConvertSegmentation(request).Applies);  // a volume's conversion
  request.Out = (dir / "bad.seg.nrrd").string();
  request.InputKind = "intensity";
  const rp::SegmentationConversion refused = logic->ConvertSegmentation(request);
  EXPECT_EQ(refused.FailureCode, 2);
  EXPECT_NE(refused.Error.find("labels.nrrd"), std::string::npos) << refused.Error;
  EXPECT_FALSE(fs::exists(request.Out));

  vtkNew<vtkRPScene> scene;
  logic->SetScene(scene);
  ASSERT_NE(logic->LoadLabelmap((dir / "labels.seg.nrrd").string(), error), nullptr) << error;
  ASSERT_TRUE(rp::SaveScene(scene, (dir / "seg.rpscene").string(), error)) << error;
  const rp::SceneConversion toSlicer = logic->ConvertScene((dir / "seg.rpscene").string(), (dir / "seg.mrml").string());
  ASSERT_TRUE(toSlicer.Error.empty()) << toSlicer.Error;
  EXPECT_EQ(toSlicer.Read.NodesByType.at("Segmentation"), 1);
  const rp::SceneConversion refusedScene = logic->ConvertScene((dir / "seg.mrml").string(), (dir / "x.nrrd").string());
  EXPECT_FALSE(refusedScene.DidRead);
  EXPECT_NE(refusedScene.Error.find("scene converts only to a scene"), std::string::npos);
}
