// DICOM in and out on real files (shared/data) and on series written here, including the bad
// series the reader must refuse with a clear message.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcddirif.h>
#include <dcmtk/dcmdata/dcrleerg.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/dcmjpeg/djencode.h>
#include <dcmtk/dcmjpeg/djrplol.h>

#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageReader.h>
#include <gdcmImageWriter.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomSeries.h"
#include "rpDicomWriter.h"
#include "rpKneePhantom.h"
#include "rpSharedData.h"
#include "rpVolumeIO.h"

namespace fs = std::filesystem;

namespace {

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

double Voxel(const rp::ImageVolume& v, int i, int j, int k) {
  int dims[3];
  v.Image->GetDimensions(dims);
  return v.Image->GetPointData()->GetScalars()->GetComponent((size_t(k) * dims[1] + j) * dims[0] + i, 0);
}

void ExpectSameVolume(const rp::ImageVolume& a, const rp::ImageVolume& b, double matrixTolerance) {
  int da[3], db[3];
  a.Image->GetDimensions(da);
  b.Image->GetDimensions(db);
  ASSERT_EQ(da[0], db[0]);
  ASSERT_EQ(da[1], db[1]);
  ASSERT_EQ(da[2], db[2]);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(a.IJKToRAS->GetElement(r, c), b.IJKToRAS->GetElement(r, c), matrixTolerance) << r << "," << c;
  vtkDataArray* sa = a.Image->GetPointData()->GetScalars();
  vtkDataArray* sb = b.Image->GetPointData()->GetScalars();
  vtkIdType differing = 0;
  for (vtkIdType i = 0; i < sa->GetNumberOfTuples(); ++i) differing += sa->GetComponent(i, 0) != sb->GetComponent(i, 0);
  EXPECT_EQ(differing, 0);
}

rp::ImageVolume SmallCT() {
  rp::KneePhantomOptions options;
  options.CTDimensions = {24, 20, 8};
  options.CTSpacing = {6.0, 7.0, 12.0};
  options.GenerateMR = false;
  options.GenerateLabels = false;
  rp::KneePhantom phantom;
  std::string error;
  EXPECT_TRUE(rp::GenerateKneePhantom(options, phantom, error)) << error;
  return phantom.CT;
}

// Re-encodes a file in place with GDCM's own encoder (JPEG 2000 here: GDCM's JPEG-LS encoder
// calls CharLS through names DCMTK's CharLS fork also exports, see rpDicomJpegLsDecoder.h).
bool EncodeWithGdcm(const fs::path& file, gdcm::TransferSyntax::TSType syntax) {
  gdcm::ImageReader reader;
  reader.SetFileName(file.c_str());
  if (!reader.Read()) return false;
  gdcm::ImageChangeTransferSyntax change;
  change.SetTransferSyntax(syntax);
  change.SetInput(reader.GetImage());
  if (!change.Change()) return false;
  gdcm::ImageWriter writer;
  writer.SetFile(reader.GetFile());
  writer.SetImage(change.GetOutput());
  writer.SetFileName(file.c_str());
  return writer.Write();
}

// Rewrites one tag of a written file (to build broken series).
void Patch(const fs::path& file, const DcmTagKey& tag, const std::string& value) {
  DcmFileFormat f;
  ASSERT_TRUE(f.loadFile(file.c_str()).good());
  ASSERT_TRUE(f.getDataset()->putAndInsertString(tag, value.c_str()).good());
  ASSERT_TRUE(f.saveFile(file.c_str(), EXS_LittleEndianExplicit).good());
}

}  // namespace

// The 3-slice GE CT. Expected values read independently with gdcmdump / gdcmraw:
// IPP z = -126.69 (01), -127.69 (02), -128.69 (03) → sorted k = 03, 02, 01; IOP identity;
// pixel spacing 0.810547; slope 1, intercept -1024; window 40/400. Stored values:
// 03.dcm (256,256)=890 (200,250)=1112 (300,200)=1003 (0,0)=-2000; 02.dcm (200,250)=1124;
// 01.dcm (256,256)=879 (300,200)=1061.
TEST(DicomSeries, GeCtThreeSlices) {
  RP_REQUIRE_SHARED_DATA("dicom/ct-3slice");
  rp::DicomScanResult scan;
  std::string error;
  ASSERT_TRUE(rp::ScanDicom(rptest::SharedDataPath("dicom/ct-3slice"), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(scan.NonDicomFiles, 1);  // LICENSE.txt, skipped and counted
  const rp::DicomSeriesInfo& s = scan.Series[0];
  EXPECT_EQ(s.Modality, "CT");
  EXPECT_EQ(s.Files.size(), 3u);
  EXPECT_EQ(s.Columns, 512);
  EXPECT_EQ(s.Rows, 512);
  EXPECT_NEAR(s.SliceSpacing, 1.0, 1e-5);
  EXPECT_TRUE(s.Problem.empty()) << s.Problem;

  rp::ImageVolume v;
  ASSERT_TRUE(rp::ReadDicomSeries(s, v, error)) << error;
  int dims[3];
  v.Image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 512);
  EXPECT_EQ(dims[1], 512);
  EXPECT_EQ(dims[2], 3);
  EXPECT_EQ(v.Image->GetScalarType(), VTK_SHORT);
  double spacing[3];
  v.GetSpacing(spacing);
  EXPECT_NEAR(spacing[0], 0.810547, 1e-6);
  EXPECT_NEAR(spacing[1], 0.810547, 1e-6);
  EXPECT_NEAR(spacing[2], 1.0, 1e-5);
  // LPS origin (-235.199997, -226.800003, -128.690002) → RAS (235.199997, 226.800003, -128.690002)
  EXPECT_NEAR(v.IJKToRAS->GetElement(0, 3), 235.199997, 1e-5);
  EXPECT_NEAR(v.IJKToRAS->GetElement(1, 3), 226.800003, 1e-5);
  EXPECT_NEAR(v.IJKToRAS->GetElement(2, 3), -128.690002, 1e-5);
  // Directions: i → -R (L), j → -A (P), k → +S.
  EXPECT_NEAR(v.IJKToRAS->GetElement(0, 0), -0.810547, 1e-6);
  EXPECT_NEAR(v.IJKToRAS->GetElement(1, 1), -0.810547, 1e-6);
  EXPECT_NEAR(v.IJKToRAS->GetElement(2, 2), 1.0, 1e-5);
  EXPECT_NEAR(v.IJKToRAS->GetElement(0, 1), 0.0, 1e-12);
  EXPECT_NEAR(v.IJKToRAS->GetElement(2, 0), 0.0, 1e-12);
  // HU = stored - 1024.
  EXPECT_EQ(Voxel(v, 256, 256, 0), 890 - 1024);
  EXPECT_EQ(Voxel(v, 200, 250, 0), 1112 - 1024);
  EXPECT_EQ(Voxel(v, 300, 200, 0), 1003 - 1024);
  EXPECT_EQ(Voxel(v, 0, 0, 0), -2000 - 1024);
  EXPECT_EQ(Voxel(v, 200, 250, 1), 1124 - 1024);
  EXPECT_EQ(Voxel(v, 256, 256, 2), 879 - 1024);
  EXPECT_EQ(Voxel(v, 300, 200, 2), 1061 - 1024);
  EXPECT_DOUBLE_EQ(v.Level, 40.0);
  EXPECT_DOUBLE_EQ(v.Window, 400.0);
}

// The Pac-Man pair. Tags (gdcmdump): IOP 0\-1\0\1\0\0, IPP -63\0\k, pixel spacing 1\1,
// 128 slices 1 mm apart. By the DICOM standard LPS(i,j,k) = (-63 + j, -i, k), i.e.
// RAS(i,j,k) = (63 - j, i, k). The NIfTI twin (float64, sform_code 2, identity srow) stores
// the same array transposed: nifti(a=j, b=i, c=k) == dicom(i, j, k) for every voxel.
// FINDING: the two files do not describe the same physical geometry. The NIfTI says
// RAS(a,b,c) = (a, b, c) = (j, i, k); the DICOM tags say (63 - j, i, k): A/P and S/I agree,
// R/L is mirrored about x = 31.5 (the DICOM writer, pydicom-based, wrote a column direction
// +L with the origin at -63 where +R/origin 0 would match the NIfTI; its PatientOrientation
// "L\R" is inconsistent with its own IOP too). The reader follows the standard, so this test
// pins both: voxels identical up to the transpose, y/z identical, x mirrored.
TEST(DicomSeries, PacmanMatchesItsNiftiTwin) {
  RP_REQUIRE_SHARED_DATA("dicom/pacsman-mr");
  RP_REQUIRE_SHARED_DATA("pacsman.nii.gz");
  rp::ImageVolume dicom;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(rp::ReadDicomVolume(rptest::SharedDataPath("dicom/pacsman-mr"), dicom, error, "", {}, &warnings)) << error;
  EXPECT_EQ(dicom.Modality, "MR");
  rp::ImageVolume nifti;
  nifti.Image = vtkSmartPointer<vtkImageData>::New();
  rp::VolumeFileData data;
  data.Image = nifti.Image;
  data.IJKToRAS = nifti.IJKToRAS;
  ASSERT_TRUE(rp::ReadVolumeFile(rptest::SharedDataPath("pacsman.nii.gz"), data, error)) << error;
  int dd[3], nd[3];
  dicom.Image->GetDimensions(dd);
  nifti.Image->GetDimensions(nd);
  ASSERT_EQ(dd[0], 128);
  ASSERT_EQ(dd[1], 128);
  ASSERT_EQ(dd[2], 128);
  ASSERT_EQ(nd[0], 128);
  ASSERT_EQ(nd[1], 128);
  ASSERT_EQ(nd[2], 128);
  const double expected[3][4] = {{0, -1, 0, 63}, {1, 0, 0, 0}, {0, 0, 1, 0}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(dicom.IJKToRAS->GetElement(r, c), expected[r][c], 1e-9) << r << c;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(nifti.IJKToRAS->GetElement(r, c), r == c ? 1.0 : 0.0, 1e-9);
  long differing = 0, nonzero = 0;
  for (int k = 0; k < 128; ++k)
    for (int j = 0; j < 128; ++j)
      for (int i = 0; i < 128; ++i) {
        const double d = Voxel(dicom, i, j, k);
        differing += d != Voxel(nifti, j, i, k);
        nonzero += d != 0.0;
      }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(nonzero, 100000);
  // Physical positions of corresponding voxels: y, z agree; x mirrored (x_dicom = 63 - x_nifti).
  for (int probe = 0; probe < 50; ++probe) {
    const int i = (probe * 37) % 128, j = (probe * 59) % 128, k = (probe * 23) % 128;
    const double ijkD[3] = {double(i), double(j), double(k)}, ijkN[3] = {double(j), double(i), double(k)};
    double rasD[3], rasN[3];
    dicom.IndexToRAS(ijkD, rasD);
    nifti.IndexToRAS(ijkN, rasN);
    EXPECT_NEAR(rasD[1], rasN[1], 1e-9);
    EXPECT_NEAR(rasD[2], rasN[2], 1e-9);
    EXPECT_NEAR(rasD[0], 63.0 - rasN[0], 1e-9);
  }
}

TEST(DicomSeries, WrittenPhantomReadsBackIdentical) {
  rp::KneePhantomOptions options;
  options.GenerateLabels = false;
  rp::KneePhantom phantom;
  std::string error;
  ASSERT_TRUE(rp::GenerateKneePhantom(options, phantom, error)) << error;
  for (const rp::ImageVolume* volume : {&phantom.CT, &phantom.MR}) {
    const fs::path dir = Scratch("roundtrip-" + volume->Modality);
    rp::DicomWriteOptions w;
    w.Modality = volume->Modality;
    rp::DicomWriteResult written;
    ASSERT_TRUE(rp::WriteDicomSeries(*volume, dir.string(), w, error, &written)) << error;
    EXPECT_EQ(written.MaxQuantizationError, 0.0);
    rp::DicomScanResult scan;
    ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error)) << error;
    ASSERT_EQ(scan.Series.size(), 1u);
    EXPECT_EQ(scan.Series[0].SeriesInstanceUID, written.SeriesInstanceUID);
    EXPECT_EQ(scan.Series[0].Modality, volume->Modality);
    rp::ImageVolume back;
    ASSERT_TRUE(rp::ReadDicomSeries(scan.Series[0], back, error)) << error;
    ExpectSameVolume(*volume, back, 1e-6);
    EXPECT_DOUBLE_EQ(back.Window, volume->Window);
    // Valid SOP class and instance UIDs.
    DcmFileFormat f;
    ASSERT_TRUE(f.loadFile(scan.Series[0].Files[0].c_str()).good());
    OFString sopClass, sopInstance;
    f.getDataset()->findAndGetOFString(DCM_SOPClassUID, sopClass);
    f.getDataset()->findAndGetOFString(DCM_SOPInstanceUID, sopInstance);
    EXPECT_EQ(std::string(sopClass.c_str()), volume->Modality == "CT" ? UID_CTImageStorage : UID_MRImageStorage);
    EXPECT_GT(sopInstance.length(), 10u);
    EXPECT_LE(sopInstance.length(), 64u);
    EXPECT_EQ(sopInstance.find_first_not_of("0123456789."), OFString_npos);
  }
}

TEST(DicomSeries, CompressedAndHeaderlessFilesDecode) {
  const rp::ImageVolume ct = SmallCT();
  const fs::path dir = Scratch("compressed");
  std::string error;
  ASSERT_TRUE(rp::WriteDicomSeries(ct, dir.string(), {}, error)) << error;
  DJEncoderRegistration::registerCodecs();
  DcmRLEEncoderRegistration::registerCodecs();
  // Re-encode: slices 1-2 JPEG lossless (process 14 SV1), 3-4 JPEG 2000 lossless (GDCM's
  // encoder), 5-6 RLE, 7 as a bare dataset without the Part-10 header: one series, DCMTK and
  // GDCM decoding side by side. (JPEG-LS: rpDicomTransferSyntaxTest, with the packaged tools.)
  int index = 0;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    DcmFileFormat f;
    ASSERT_TRUE(f.loadFile(file.c_str()).good());
    DcmDataset* ds = f.getDataset();
    E_TransferSyntax xfer = EXS_LittleEndianExplicit;
    if (index == 1 || index == 2) xfer = EXS_JPEGProcess14SV1;
    if (index == 5 || index == 6) xfer = EXS_RLELossless;
    if (index == 3 || index == 4) {
      ASSERT_TRUE(EncodeWithGdcm(file, gdcm::TransferSyntax::JPEG2000Lossless));
    } else if (xfer != EXS_LittleEndianExplicit) {
      DJ_RPLossless params;
      ASSERT_TRUE(ds->chooseRepresentation(xfer, &params).good()) << index;
      ASSERT_TRUE(ds->canWriteXfer(xfer)) << index;
      ASSERT_TRUE(f.saveFile(file.c_str(), xfer).good());
    } else if (index == 7) {
      ASSERT_TRUE(ds->saveFile(file.c_str(), EXS_LittleEndianImplicit).good());
    }
    ++index;
  }
  DcmRLEEncoderRegistration::cleanup();
  DJEncoderRegistration::cleanup();
  rp::ImageVolume back;
  ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), back, error)) << error;
  ExpectSameVolume(ct, back, 1e-6);
}

TEST(DicomSeries, BadSeriesGetClearMessages) {
  const rp::ImageVolume ct = SmallCT();  // 8 slices, 12 mm apart
  std::string error;
  auto writeSeries = [&](const std::string& name) {
    const fs::path dir = Scratch(name);
    EXPECT_TRUE(rp::WriteDicomSeries(ct, dir.string(), {}, error)) << error;
    return dir;
  };
  rp::ImageVolume untouched = SmallCT();
  rp::ImageVolume v = untouched;

  {  // A missing slice: refused by default, naming where; loaded with the true geometry on request.
    const fs::path dir = writeSeries("missing");
    fs::remove(dir / "IM00004.dcm");
    std::ofstream(dir / "notes.txt") << "not a DICOM file\n";
    rp::DicomScanResult scan;
    ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error));
    EXPECT_EQ(scan.NonDicomFiles, 1);
    ASSERT_EQ(scan.Series.size(), 1u);
    EXPECT_NE(scan.Series[0].Problem.find("1 missing slice"), std::string::npos) << scan.Series[0].Problem;
    EXPECT_FALSE(rp::ReadDicomSeries(scan.Series[0], v, error));
    EXPECT_NE(error.find("missing slice"), std::string::npos) << error;
    EXPECT_NE(error.find("IM00003.dcm"), std::string::npos) << error;
    EXPECT_NE(error.find("IM00005.dcm"), std::string::npos) << error;
    EXPECT_EQ(v.Image, untouched.Image);  // nothing replaced on failure
    rp::DicomReadOptions resample;
    resample.ResampleIrregularSpacing = true;
    std::vector<std::string> warnings;
    rp::ImageVolume r;
    ASSERT_TRUE(rp::ReadDicomSeries(scan.Series[0], r, error, resample, &warnings)) << error;
    ASSERT_FALSE(warnings.empty());
    int dims[3];
    r.Image->GetDimensions(dims);
    EXPECT_EQ(dims[2], 8);  // the gap is filled: same extent, same spacing
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 3; ++row)
        EXPECT_NEAR(r.IJKToRAS->GetElement(row, c), ct.IJKToRAS->GetElement(row, c), 1e-6);
    EXPECT_DOUBLE_EQ(Voxel(r, 12, 10, 2), Voxel(ct, 12, 10, 2));  // real slices unchanged
    EXPECT_NEAR(Voxel(r, 12, 10, 3), 0.5 * (Voxel(ct, 12, 10, 2) + Voxel(ct, 12, 10, 4)), 1e-3);
  }
  {  // Uneven spacing.
    const fs::path dir = writeSeries("uneven");
    DcmFileFormat f;
    ASSERT_TRUE(f.loadFile((dir / "IM00005.dcm").c_str()).good());
    Float64 z = 0;
    f.getDataset()->findAndGetFloat64(DCM_ImagePositionPatient, z, 2);
    // Move slice 5 by 3 mm along z (x, y kept exactly).
    OFString x, y;
    f.getDataset()->findAndGetOFString(DCM_ImagePositionPatient, x, 0);
    f.getDataset()->findAndGetOFString(DCM_ImagePositionPatient, y, 1);
    Patch(dir / "IM00005.dcm", DCM_ImagePositionPatient,
          std::string(x.c_str()) + "\\" + y.c_str() + "\\" + std::to_string(z + 3.0));
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("uneven slice spacing"), std::string::npos) << error;
    EXPECT_NE(error.find("IM00005.dcm"), std::string::npos) << error;
  }
  {  // Gantry tilt: positions shift along y as z increases (a 20 degree tilt).
    const fs::path dir = writeSeries("tilt");
    for (int k = 0; k < 8; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "IM%05d.dcm", k + 1);
      DcmFileFormat f;
      ASSERT_TRUE(f.loadFile((dir / name).c_str()).good());
      Float64 p[3];
      for (int a = 0; a < 3; ++a) f.getDataset()->findAndGetFloat64(DCM_ImagePositionPatient, p[a], a);
      Patch(dir / name, DCM_ImagePositionPatient,
            std::to_string(p[0]) + "\\" + std::to_string(p[1] + k * 12.0 * std::tan(20 * M_PI / 180)) + "\\" +
                std::to_string(p[2]));
    }
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("gantry tilt of 20.0 degrees"), std::string::npos) << error;
  }
  {  // One slice in another orientation: two stacks under one UID, the read refused naming both.
    const fs::path dir = writeSeries("mixed-orientation");
    Patch(dir / "IM00003.dcm", DCM_ImageOrientationPatient, "1\\0\\0\\0\\0.9\\0.43588989");
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("holds 2 stacks"), std::string::npos) << error;
    EXPECT_NE(error.find("#1 (axial, 24x20x7"), std::string::npos) << error;
    EXPECT_NE(error.find("#2 (oblique axial (25.8°), 24x20x1"), std::string::npos) << error;
    rp::DicomScanResult scan;
    ASSERT_TRUE(rp::ScanDicom(dir.string(), scan, error)) << error;
    ASSERT_EQ(scan.Series.size(), 2u);
    // The axial stack lost a slice to the other one: refused as a gap; the odd slice loads alone.
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error, scan.Series[0].StackID));
    EXPECT_NE(error.find("1 missing slice"), std::string::npos) << error;
    rp::ImageVolume single;
    ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), single, error, scan.Series[1].StackID)) << error;
    EXPECT_NEAR(single.IJKToRAS->GetElement(2, 1), 0.43588989 * 7.0, 1e-6);  // j axis: column direction (S part)
    const fs::path dir2 = writeSeries("mixed-size");
    DcmFileFormat f;
    ASSERT_TRUE(f.loadFile((dir2 / "IM00006.dcm").c_str()).good());
    f.getDataset()->putAndInsertUint16(DCM_Rows, 10);
    ASSERT_TRUE(f.saveFile((dir2 / "IM00006.dcm").c_str(), EXS_LittleEndianExplicit).good());
    EXPECT_FALSE(rp::ReadDicomVolume(dir2.string(), v, error));
    EXPECT_NE(error.find("holds 2 stacks"), std::string::npos) << error;
    EXPECT_NE(error.find("24x10x1"), std::string::npos) << error;
  }
  {  // A truncated file is named.
    const fs::path dir = writeSeries("truncated");
    const fs::path file = dir / "IM00002.dcm";
    const auto size = fs::file_size(file);
    fs::resize_file(file, size / 2);
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("IM00002.dcm"), std::string::npos) << error;
  }
  {  // JPEG 2000 (decoded by GDCM): a damaged codestream is an error naming the file and the syntax.
    const fs::path dir = writeSeries("j2k");
    const fs::path file = dir / "IM00004.dcm";
    ASSERT_TRUE(EncodeWithGdcm(file, gdcm::TransferSyntax::JPEG2000Lossless));
    rp::ImageVolume intact;
    ASSERT_TRUE(rp::ReadDicomVolume(dir.string(), intact, error)) << error;
    ExpectSameVolume(ct, intact, 1e-6);
    {  // Damage the codestream's image header (SIZ marker segment after SOC): lossless JPEG 2000
      // has no checksum, so damage in the coded data itself may decode silently to other values.
      std::ifstream in(file, std::ios::binary);
      std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      in.close();
      const size_t soc = bytes.find(std::string("\xff\x4f\xff\x51", 4));
      ASSERT_NE(soc, std::string::npos);
      std::fill(bytes.begin() + soc + 4, bytes.begin() + soc + 40, '\xff');
      std::ofstream(file, std::ios::binary).write(bytes.data(), bytes.size());
    }
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("IM00004.dcm"), std::string::npos) << error;
    EXPECT_NE(error.find("JPEG 2000"), std::string::npos) << error;
  }
  {  // A folder with no DICOM at all.
    const fs::path dir = Scratch("empty");
    std::ofstream(dir / "a.txt") << "hello";
    EXPECT_FALSE(rp::ReadDicomVolume(dir.string(), v, error));
    EXPECT_NE(error.find("no DICOM image series"), std::string::npos) << error;
    EXPECT_FALSE(rp::ReadDicomVolume((dir / "nope").string(), v, error));
    EXPECT_NE(error.find("no such file"), std::string::npos) << error;
  }
  EXPECT_EQ(v.Image, untouched.Image);
}

TEST(DicomSeries, DicomdirListsItsSeries) {
  const rp::ImageVolume ct = SmallCT();
  const fs::path root = Scratch("dicomdir");
  const fs::path series = root / "DICOM" / "SERIES1";
  std::string error;
  ASSERT_TRUE(rp::WriteDicomSeries(ct, series.string(), {}, error)) << error;
  // DICOM file IDs: upper case, no extension.
  std::vector<std::string> ids;
  for (const auto& e : fs::directory_iterator(series)) {
    const std::string id = e.path().stem().string();
    fs::rename(e.path(), series / id);
    ids.push_back(id);
  }
  std::ofstream(root / "README.TXT") << "not DICOM";
  DicomDirInterface dir;
  ASSERT_TRUE(dir.createNewDicomDir(DicomDirInterface::AP_GeneralPurpose, (root / "DICOMDIR").c_str()).good());
  for (const auto& id : ids) ASSERT_TRUE(dir.addDicomFile(("DICOM/SERIES1/" + id).c_str(), root.c_str()).good()) << id;
  ASSERT_TRUE(dir.writeDicomDir().good());

  rp::DicomScanResult scan;
  ASSERT_TRUE(rp::ScanDicom((root / "DICOMDIR").string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(scan.FilesExamined, 8);  // only the referenced images, not README.TXT
  EXPECT_EQ(scan.Series[0].Files.size(), 8u);
  rp::ImageVolume back;
  ASSERT_TRUE(rp::ReadDicomVolume((root / "DICOMDIR").string(), back, error)) << error;
  ExpectSameVolume(ct, back, 1e-6);
  // Scanning the folder instead finds the same series and counts the DICOMDIR as non-image.
  ASSERT_TRUE(rp::ScanDicom(root.string(), scan, error)) << error;
  ASSERT_EQ(scan.Series.size(), 1u);
  EXPECT_EQ(scan.NonImageDicomFiles, 1);
  EXPECT_EQ(scan.NonDicomFiles, 1);
}
