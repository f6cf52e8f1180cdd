// Series as scanners write them, made from the real series in shared/data: one folder holding
// several series; one SeriesInstanceUID holding a three-plane localizer (split into stacks,
// each loadable, refused as a whole naming the orientations); an oblique MR stack compressed
// with JPEG 2000 (its IJK-to-RAS must be what the headers say); an Enhanced MR multi-frame file
// with a position per frame (made with DCMTK's API: no packaged tool builds one).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomSeries.h"
#include "rpDicomTestTools.h"
#include "rpSharedData.h"

namespace fs = std::filesystem;
using rp::testing::DicomFiles;
using rp::testing::FindTool;
using rp::testing::RunTool;
using rp::testing::Scratch;

namespace {

const fs::path kData = ROBOPLAN_SHARED_DATA_DIR;

#define REQUIRE_DATA(path) RP_REQUIRE_SHARED_DATA((path).string())
#define REQUIRE_TOOL(variable, name, package) \
  const std::string variable = FindTool(name); \
  if (variable.empty()) GTEST_SKIP() << name << " not found on PATH (Debian package " << package << ")"

std::string Ds(double v) {  // a DICOM decimal string (at most 16 characters)
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", std::abs(v) < 1e-12 ? 0.0 : v);
  return text;
}
std::string Ds(const double* v, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += (i ? "\\" : "") + Ds(v[i]);
  return s;
}

// Copies `files` into `dir` (keeping names) and returns the copies.
std::vector<fs::path> CopyInto(const std::vector<fs::path>& files, const fs::path& dir) {
  fs::create_directories(dir);
  std::vector<fs::path> copies;
  for (const fs::path& f : files) {
    copies.push_back(dir / f.filename());
    fs::copy_file(f, copies.back(), fs::copy_options::overwrite_existing);
  }
  return copies;
}

void ExpectMatrix(const rp::ImageVolume& v, const double expected[3][4], double tolerance) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(v.IJKToRAS->GetElement(r, c), expected[r][c], tolerance) << r << "," << c;
}

void ExpectSameVoxels(const rp::ImageVolume& a, const rp::ImageVolume& b) {
  int da[3], db[3];
  a.Image->GetDimensions(da);
  b.Image->GetDimensions(db);
  ASSERT_EQ(std::vector<int>(da, da + 3), std::vector<int>(db, db + 3));
  vtkDataArray* x = a.Image->GetPointData()->GetScalars();
  vtkDataArray* y = b.Image->GetPointData()->GetScalars();
  vtkIdType differing = 0;
  for (vtkIdType i = 0; i < x->GetNumberOfTuples(); ++i) differing += x->GetComponent(i, 0) != y->GetComponent(i, 0);
  EXPECT_EQ(differing, 0);
}

}  // namespace

TEST(DicomStacks, OneFolderSeveralSeries) {
  REQUIRE_DATA(kData / "knee-ct-vhf/dicom");
  const fs::path dir = Scratch("several");
  CopyInto(DicomFiles(kData / "dicom/ct-3slice"), dir / "ge");
  CopyInto(DicomFiles(kData / "knee-ct-vhf/dicom", 4), dir / "knee");
  CopyInto(DicomFiles(kData / "dicom/pacsman-mr", 4), dir / "mr");
  rp::DicomScanResult scan;
  std::string error;
  ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 3u);
  for (const auto& s : scan.Series) {
    EXPECT_EQ(s.StackCount, 1);
    EXPECT_EQ(s.StackID, s.SeriesInstanceUID);  // one stack: the ID is the UID
    EXPECT_TRUE(s.Problem.empty()) << s.Problem;
    rp::ImageVolume v;
    EXPECT_TRUE(rp::ReadDicomVolume(dir.string(), v, error, s.StackID)) << error;
  }
  rp::ImageVolume v;
  EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
  EXPECT_NE(error.find("holds 3 DICOM series or stacks"), std::string::npos) << error;
  for (const auto& s : scan.Series) EXPECT_NE(error.find(s.StackID), std::string::npos) << error;
}

// Nine Pac-Man MR files under their one SeriesInstanceUID, relabelled (dcmodify) as a localizer:
// three axial slices as written, three sagittal, three coronal, 5 mm apart.
TEST(DicomStacks, ThreePlaneLocalizerSplitsIntoStacks) {
  REQUIRE_DATA(kData / "dicom/pacsman-mr");
  REQUIRE_TOOL(dcmodify, "dcmodify", "dcmtk");
  const fs::path dir = Scratch("localizer");
  const std::vector<fs::path> all = DicomFiles(kData / "dicom/pacsman-mr");
  std::vector<fs::path> picked(all.begin() + 60, all.begin() + 69);
  const std::vector<fs::path> files = CopyInto(picked, dir);
  const std::string log = (dir / "tool.log").string();
  for (int i = 0; i < 3; ++i) {
    const std::string sagittal = "-" + std::to_string(10 - 5 * i) + "\\-64\\64";
    ASSERT_EQ(RunTool(dcmodify, {"-nb", "-m", "(0020,0037)=0\\1\\0\\0\\0\\-1", "-m", "(0020,0032)=" + sagittal,
                                 files[3 + i].string()}, log), 0);
    const std::string coronal = "-64\\" + std::to_string(-5 + 5 * i) + "\\64";
    ASSERT_EQ(RunTool(dcmodify, {"-nb", "-m", "(0020,0037)=1\\0\\0\\0\\0\\-1", "-m", "(0020,0032)=" + coronal,
                                 files[6 + i].string()}, log), 0);
  }
  rp::DicomScanResult scan;
  std::string error;
  ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 3u);
  const char* names[3] = {"axial", "sagittal", "coronal"};
  for (int s = 0; s < 3; ++s) {
    EXPECT_EQ(scan.Series[s].SeriesInstanceUID, scan.Series[0].SeriesInstanceUID);
    EXPECT_EQ(scan.Series[s].StackIndex, s + 1);
    EXPECT_EQ(scan.Series[s].StackCount, 3);
    EXPECT_EQ(scan.Series[s].StackID, scan.Series[0].SeriesInstanceUID + "#" + std::to_string(s + 1));
    EXPECT_EQ(scan.Series[s].OrientationName, names[s]);
    EXPECT_EQ(scan.Series[s].Slices, 3);
    EXPECT_TRUE(scan.Series[s].Problem.empty()) << scan.Series[s].Problem;
  }
  // The whole series is refused, naming its stacks and their orientations.
  rp::ImageVolume v;
  EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
  EXPECT_NE(error.find("holds 3 stacks"), std::string::npos) << error;
  for (const char* name : names) EXPECT_NE(error.find(std::string("(") + name + ", 128x128x3"), std::string::npos) << error;
  // Each stack loads with the geometry its headers give (worked out by hand from the tags).
  rp::ImageVolume axial, sagittal, coronal;
  ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), axial, error, scan.Series[0].StackID)) << error;
  ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), sagittal, error, scan.Series[1].StackID)) << error;
  ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), coronal, error, scan.Series[2].StackID)) << error;
  // Axial: IOP 0\-1\0\1\0\0, IPP -63\0\60..62 → RAS(i,j,k) = (63 - j, i, 60 + k).
  const double axialRAS[3][4] = {{0, -1, 0, 63}, {1, 0, 0, 0}, {0, 0, 1, 60}};
  ExpectMatrix(axial, axialRAS, 1e-9);
  // Sagittal: IOP 0\1\0\0\0\-1 (normal -x in LPS), IPP x = -10, -5, 0: sorted along the normal the
  // first slice is x = 0; LPS(i,j,k) = (-5k, -64 + i, 64 - j) → RAS = (5k, 64 - i, 64 - j).
  const double sagittalRAS[3][4] = {{0, 0, 5, 0}, {-1, 0, 0, 64}, {0, -1, 0, 64}};
  ExpectMatrix(sagittal, sagittalRAS, 1e-9);
  // Coronal: IOP 1\0\0\0\0\-1 (normal +y in LPS), IPP y = -5, 0, 5 → LPS(i,j,k) = (-64 + i, -5 + 5k,
  // 64 - j) → RAS = (64 - i, 5 - 5k, 64 - j).
  const double coronalRAS[3][4] = {{-1, 0, 0, 64}, {0, 0, -5, 5}, {0, -1, 0, 64}};
  ExpectMatrix(coronal, coronalRAS, 1e-9);
  // Voxels: each stack holds its files' pixels (compare with the untouched originals).
  rp::ImageVolume originalAxial;
  const fs::path originals = Scratch("localizer-originals");
  CopyInto(std::vector<fs::path>(picked.begin(), picked.begin() + 3), originals);
  ASSERT_TRUE(rp::ReadDicomVolume(originals.string(), originalAxial, error)) << error;
  ExpectSameVoxels(axial, originalAxial);
}

// The issue's case, built as closely as our real data allows: an MR series made oblique
// (IOP and IPP rotated together by dcmodify, 25 degrees about x then 15 about z) and
// compressed with JPEG 2000 by gdcmconv. Voxels as in the original, IJK-to-RAS as the tags say.
TEST(DicomStacks, ObliqueJpeg2000MrKeepsItsGeometry) {
  REQUIRE_DATA(kData / "dicom/pacsman-mr");
  REQUIRE_TOOL(dcmodify, "dcmodify", "dcmtk");
  REQUIRE_TOOL(gdcmconv, "gdcmconv", "libgdcm-tools");
  const fs::path dir = Scratch("oblique"), originals = Scratch("oblique-originals"), j2k = Scratch("oblique-j2k");
  const std::vector<fs::path> all = DicomFiles(kData / "dicom/pacsman-mr");
  const std::vector<fs::path> picked(all.begin() + 40, all.begin() + 48);
  CopyInto(picked, originals);
  const std::vector<fs::path> files = CopyInto(picked, dir);
  const double ax = 25 * M_PI / 180, az = 15 * M_PI / 180;
  const double rx[3][3] = {{1, 0, 0}, {0, std::cos(ax), -std::sin(ax)}, {0, std::sin(ax), std::cos(ax)}};
  const double rz[3][3] = {{std::cos(az), -std::sin(az), 0}, {std::sin(az), std::cos(az), 0}, {0, 0, 1}};
  double r[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = rz[i][0] * rx[0][j] + rz[i][1] * rx[1][j] + rz[i][2] * rx[2][j];
  auto rotate = [&](const double in[3], double out[3]) {
    for (int i = 0; i < 3; ++i) out[i] = r[i][0] * in[0] + r[i][1] * in[1] + r[i][2] * in[2];
  };
  const double row[3] = {0, -1, 0}, col[3] = {1, 0, 0};  // the series' own IOP
  double iop[6];
  rotate(row, iop);
  rotate(col, iop + 3);
  const std::string log = (dir / "tool.log").string();
  std::vector<std::array<double, 3>> written;
  for (size_t k = 0; k < files.size(); ++k) {
    const double p[3] = {-63, 0, 40.0 + k};  // IPP as in the file (slice40.dcm ... slice47.dcm)
    std::array<double, 3> q;
    rotate(p, q.data());
    written.push_back(q);
    ASSERT_EQ(RunTool(dcmodify, {"-nb", "-m", "(0020,0037)=" + Ds(iop, 6), "-m", "(0020,0032)=" + Ds(q.data(), 3),
                                 files[k].string()}, log), 0);
    ASSERT_EQ(RunTool(gdcmconv, {"--j2k", files[k].string(), (j2k / files[k].filename()).string()}, log), 0);
  }
  rp::DicomScanResult scan;
  std::string error;
  ASSERT_TRUE(rp::ScanDicom(j2k.string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(scan.Series[0].TransferSyntaxUID, "1.2.840.10008.1.2.4.90");
  EXPECT_EQ(scan.Series[0].OrientationName, "oblique axial (25.0°)");
  rp::ImageVolume oblique, original;
  ASSERT_TRUE(rp::ReadDicomSeries(scan.Series[0], oblique, error)) << error;
  ASSERT_TRUE(rp::ReadDicomVolume(originals.string(), original, error)) << error;
  ExpectSameVoxels(oblique, original);
  // Expected IJK-to-RAS from the header values: columns = row cosine x column spacing, column
  // cosine x row spacing, normal x slice gap (1 mm); origin = IPP of slice40; LPS → RAS.
  double expected[3][4];
  const double normal[3] = {iop[1] * iop[5] - iop[2] * iop[4], iop[2] * iop[3] - iop[0] * iop[5],
                            iop[0] * iop[4] - iop[1] * iop[3]};
  const double sign[3] = {-1, -1, 1};
  for (int i = 0; i < 3; ++i) {
    expected[i][0] = sign[i] * iop[i];
    expected[i][1] = sign[i] * iop[3 + i];
    expected[i][2] = sign[i] * normal[i];
    expected[i][3] = sign[i] * written[0][i];
  }
  ExpectMatrix(oblique, expected, 2e-6);  // DS strings carry 10 significant digits
}

// An Enhanced MR Image Storage file (one file, ten frames, a PlanePositionSequence per frame,
// frames stored in reverse order) made with DCMTK's API from ten Pac-Man slices: reads as the
// ten single files do; then JPEG 2000-compressed by gdcmconv, the same again.
TEST(DicomStacks, EnhancedMultiFrameLoadsFrameByFrame) {
  REQUIRE_DATA(kData / "dicom/pacsman-mr");
  const fs::path singles = Scratch("multiframe-singles"), dir = Scratch("multiframe");
  const std::vector<fs::path> all = DicomFiles(kData / "dicom/pacsman-mr");
  const std::vector<fs::path> picked(all.begin() + 20, all.begin() + 30);
  CopyInto(picked, singles);
  const int frames = static_cast<int>(picked.size());
  DcmFileFormat out;
  DcmDataset* ds = out.getDataset();
  std::vector<Uint16> pixels;
  for (int f = 0; f < frames; ++f) {
    const fs::path& source = picked[frames - 1 - f];  // reverse order: sorting must use the positions
    DcmFileFormat in;
    ASSERT_TRUE(in.loadFile(source.c_str()).good());
    DcmDataset* src = in.getDataset();
    if (f == 0) {
      ds->copyFrom(*src);
      for (const DcmTagKey& tag : {DCM_ImagePositionPatient, DCM_ImageOrientationPatient, DCM_PixelSpacing,
                                   DCM_RescaleIntercept, DCM_RescaleSlope, DCM_SliceThickness, DCM_InstanceNumber})
        delete ds->remove(tag);
      ds->putAndInsertString(DCM_SOPClassUID, UID_EnhancedMRImageStorage);
      ds->putAndInsertString(DCM_NumberOfFrames, std::to_string(frames).c_str());
      DcmItem* shared = nullptr;
      DcmItem* group = nullptr;
      ASSERT_TRUE(ds->findOrCreateSequenceItem(DCM_SharedFunctionalGroupsSequence, shared, 0).good());
      ASSERT_TRUE(shared->findOrCreateSequenceItem(DCM_PixelMeasuresSequence, group, 0).good());
      group->putAndInsertString(DCM_PixelSpacing, "1\\1");
      group->putAndInsertString(DCM_SliceThickness, "1");
      ASSERT_TRUE(shared->findOrCreateSequenceItem(DCM_PlaneOrientationSequence, group, 0).good());
      group->putAndInsertString(DCM_ImageOrientationPatient, "0\\-1\\0\\1\\0\\0");
      ASSERT_TRUE(shared->findOrCreateSequenceItem(DCM_PixelValueTransformationSequence, group, 0).good());
      group->putAndInsertString(DCM_RescaleIntercept, "0");
      group->putAndInsertString(DCM_RescaleSlope, "1");
    }
    OFString position;
    ASSERT_TRUE(src->findAndGetOFStringArray(DCM_ImagePositionPatient, position).good());
    DcmItem* frame = nullptr;
    DcmItem* group = nullptr;
    ASSERT_TRUE(ds->findOrCreateSequenceItem(DCM_PerFrameFunctionalGroupsSequence, frame, -2).good());
    ASSERT_TRUE(frame->findOrCreateSequenceItem(DCM_PlanePositionSequence, group, 0).good());
    group->putAndInsertString(DCM_ImagePositionPatient, position.c_str());
    const Uint16* data = nullptr;
    ASSERT_TRUE(src->findAndGetUint16Array(DCM_PixelData, data).good());
    pixels.insert(pixels.end(), data, data + 128 * 128);
  }
  ASSERT_TRUE(ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), pixels.size()).good());
  const fs::path file = dir / "enhanced.dcm";
  ASSERT_TRUE(out.saveFile(file.c_str(), EXS_LittleEndianExplicit).good());

  rp::DicomScanResult scan;
  std::string error;
  ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(scan.Series[0].Files.size(), 1u);
  EXPECT_EQ(scan.Series[0].Slices, frames);
  EXPECT_NEAR(scan.Series[0].SliceSpacing, 1.0, 1e-9);
  EXPECT_TRUE(scan.Series[0].Problem.empty()) << scan.Series[0].Problem;
  rp::ImageVolume multi, single;
  ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), multi, error)) << error;
  ASSERT_TRUE(rp::ReadDicomVolume(singles.string(), single, error)) << error;
  ExpectSameVoxels(multi, single);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(multi.IJKToRAS->GetElement(r, c), single.IJKToRAS->GetElement(r, c), 1e-9);

  if (const std::string gdcmconv = FindTool("gdcmconv"); !gdcmconv.empty()) {
    const fs::path j2k = Scratch("multiframe-j2k");
    ASSERT_EQ(RunTool(gdcmconv, {"--j2k", file.string(), (j2k / "enhanced.dcm").string()}, (j2k / "log").string()), 0);
    rp::ImageVolume compressed;
    ASSERT_TRUE(rp::ReadDicomVolume(j2k.string(), compressed, error)) << error;
    ExpectSameVoxels(compressed, single);
  } else {
    std::cout << "gdcmconv not found (Debian package libgdcm-tools): multi-frame JPEG 2000 not checked\n";
  }

  // Without per-frame positions the frames cannot be placed: refused, naming the file.
  delete ds->remove(DCM_PerFrameFunctionalGroupsSequence);
  const fs::path legacy = Scratch("multiframe-legacy");
  ASSERT_TRUE(out.saveFile((legacy / "enhanced.dcm").c_str(), EXS_LittleEndianExplicit).good());
  rp::ImageVolume v;
  EXPECT_FALSE(rp::ReadDicomVolume(legacy.string(), v, error));
  EXPECT_NE(error.find("multi-frame image without a position per frame (10 frames in enhanced.dcm"),
            std::string::npos)
      << error;
}
