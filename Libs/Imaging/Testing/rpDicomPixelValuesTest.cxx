// DICOM pixel values that must never come back silently wrong: Modality LUT Sequence, 32-bit
// greyscale (OB/OW, implicit/explicit/big-endian VR, RLE), Float and Double Float Pixel Data,
// every sample of a Big Endian file (checked by pydicom, an independent reader),
// invalid PixelSpacing, palette and other colour images, legacy multi-frame files (MR with
// Spacing Between Slices, RT Dose with its Grid Frame Offset Vector). Every file is written here
// with DCMTK's API, some re-encoded with DCMTK's command-line tools; the expected voxels are
// computed from the stored values by the standard's formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>

#include <nlohmann/json.hpp>

#include "rpDicomPython.h"
#include "rpDicomSeries.h"
#include "rpDicomTestTools.h"

namespace fs = std::filesystem;

namespace {

constexpr int Columns = 6, Rows = 4;

// A minimal single- or multi-frame greyscale image (Secondary Capture unless `modality` says
// otherwise), pixel data left to the caller.
void Header(DcmDataset* ds, const std::string& modality, int frames, int bits, bool isSigned, double z,
            const std::string& seriesUID) {
  char uid[100];
  ds->putAndInsertString(DCM_SOPClassUID, modality == "RTDOSE" ? UID_RTDoseStorage : UID_SecondaryCaptureImageStorage);
  ds->putAndInsertString(DCM_SOPInstanceUID, dcmGenerateUniqueIdentifier(uid, SITE_INSTANCE_UID_ROOT));
  ds->putAndInsertString(DCM_StudyInstanceUID, "1.2.826.0.1.3680043.10.1234.1");
  ds->putAndInsertString(DCM_SeriesInstanceUID, seriesUID.c_str());
  ds->putAndInsertString(DCM_Modality, modality.c_str());
  ds->putAndInsertString(DCM_PatientName, "Pixel^Values");
  ds->putAndInsertUint16(DCM_Rows, Rows);
  ds->putAndInsertUint16(DCM_Columns, Columns);
  ds->putAndInsertUint16(DCM_SamplesPerPixel, 1);
  ds->putAndInsertString(DCM_PhotometricInterpretation, "MONOCHROME2");
  ds->putAndInsertUint16(DCM_BitsAllocated, bits);
  ds->putAndInsertUint16(DCM_BitsStored, bits);
  ds->putAndInsertUint16(DCM_HighBit, bits - 1);
  ds->putAndInsertUint16(DCM_PixelRepresentation, isSigned ? 1 : 0);
  ds->putAndInsertString(DCM_ImageOrientationPatient, "1\\0\\0\\0\\1\\0");
  ds->putAndInsertString(DCM_ImagePositionPatient, ("-10\\-20\\" + std::to_string(z)).c_str());
  ds->putAndInsertString(DCM_PixelSpacing, "0.5\\0.75");
  if (frames > 1) ds->putAndInsertString(DCM_NumberOfFrames, std::to_string(frames).c_str());
}

void Save(DcmFileFormat& file, const fs::path& path, E_TransferSyntax syntax = EXS_LittleEndianExplicit) {
  ASSERT_TRUE(file.saveFile(path.c_str(), syntax).good()) << path;
}

double Voxel(const rp::ImageVolume& v, int i, int j, int k) {
  return v.Image->GetPointData()->GetScalars()->GetComponent((size_t(k) * Rows + j) * Columns + i, 0);
}

std::string Join(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

bool Read(const fs::path& path, rp::ImageVolume& volume, std::string& error, std::vector<std::string>* warnings = nullptr) {
  return rp::ReadDicomVolume(path.string(), volume, error, "", {}, warnings);
}

}  // namespace

TEST(DicomPixelValues, ModalityLutSequenceMapsEveryStoredValue) {
  const fs::path dir = rp::testing::Scratch("modality-lut");
  for (const bool isSigned : {false, true}) {
    // LUT: 30 entries from stored value -5 (signed) or 5 (unsigned), output 1000 + i*i; stored
    // values run below, through and above the table (clamped to its ends, PS3.3 C.11.1.1).
    const int first = isSigned ? -5 : 5;
    std::vector<Uint16> lut(30);
    for (int i = 0; i < 30; ++i) lut[i] = static_cast<Uint16>(1000 + i * i);
    std::vector<int> stored(Columns * Rows);
    for (int i = 0; i < Columns * Rows; ++i) stored[i] = first - 2 + i * 32 / (Columns * Rows) + (i % 3);
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    Header(ds, "OT", 1, 16, isSigned, 0, isSigned ? "1.2.826.0.1.3680043.10.1234.2" : "1.2.826.0.1.3680043.10.1234.3");
    std::vector<Uint16> pixels(stored.begin(), stored.end());  // two's complement when signed
    ASSERT_TRUE(ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), pixels.size()).good());
    DcmItem* item = nullptr;
    ASSERT_TRUE(ds->findOrCreateSequenceItem(DCM_ModalityLUTSequence, item, -2).good());
    // LUT Descriptor (US; the first mapped value in two's complement when the pixels are signed).
    const Uint16 descriptor[3] = {30, static_cast<Uint16>(first), 16};
    auto* element = new DcmUnsignedShort(DcmTag(DCM_LUTDescriptor, EVR_US));
    element->putUint16Array(descriptor, 3);
    item->insert(element, true);
    item->putAndInsertUint16Array(DCM_LUTData, lut.data(), lut.size());
    item->putAndInsertString(DCM_ModalityLUTType, "HU");
    const fs::path path = dir / (isSigned ? "signed.dcm" : "unsigned.dcm");
    Save(file, path);
    rp::ImageVolume v;
    std::string error;
    ASSERT_TRUE(Read(path, v, error)) << error;
    for (int i = 0; i < Columns * Rows; ++i) {
      const int index = std::clamp(stored[i] - first, 0, 29);
      EXPECT_EQ(Voxel(v, i % Columns, i / Columns, 0), lut[index]) << "stored " << stored[i];
    }
  }
}

TEST(DicomPixelValues, ThirtyTwoBitGreyscaleReadsInEveryEncoding) {
  const fs::path dir = rp::testing::Scratch("thirty-two-bit");
  const std::string log = (dir / "tools.log").string();
  const std::string dcmcrle = rp::testing::FindTool("dcmcrle");
  for (const bool isSigned : {false, true}) {
    // Values beyond 16 bits (and beyond 2^31 unsigned), rescaled by 3 and -7.
    std::vector<Uint32> raw(Columns * Rows);
    std::vector<double> expected(raw.size());
    for (size_t i = 0; i < raw.size(); ++i) {
      const int64_t value = isSigned ? (int64_t(i) - 12) * 123457 : int64_t(i) * 150000000;
      raw[i] = static_cast<Uint32>(value);
      expected[i] = double(value) * 3 - 7;
    }
    for (const std::string vr : {"OW", "OB"}) {
      DcmFileFormat file;
      DcmDataset* ds = file.getDataset();
      Header(ds, "OT", 1, 32, isSigned, 0, "1.2.826.0.1.3680043.10.1234.4");
      ds->putAndInsertString(DCM_RescaleSlope, "3");
      ds->putAndInsertString(DCM_RescaleIntercept, "-7");
      if (vr == "OW")
        ASSERT_TRUE(ds->putAndInsertUint16Array(DCM_PixelData, reinterpret_cast<Uint16*>(raw.data()), raw.size() * 2).good());
      else
        ASSERT_TRUE(ds->putAndInsertUint8Array(DCM_PixelData, reinterpret_cast<Uint8*>(raw.data()), raw.size() * 4).good());
      const std::string stem = std::string(isSigned ? "signed-" : "unsigned-") + vr;
      const fs::path explicitFile = dir / (stem + "-explicit.dcm");
      Save(file, explicitFile);
      std::vector<fs::path> variants = {explicitFile};
      const fs::path implicitFile = dir / (stem + "-implicit.dcm");
      Save(file, implicitFile, EXS_LittleEndianImplicit);
      variants.push_back(implicitFile);
      // (Big endian: BigEndianSamplesReadWhole below. dcmconv +tb writes a 32-bit sample's two
      // 16-bit words low word first, not the sample most significant byte first.)
      if (!dcmcrle.empty()) {
        variants.push_back(dir / (stem + "-rle.dcm"));
        ASSERT_EQ(rp::testing::RunTool(dcmcrle, {explicitFile.string(), variants.back().string()}, log), 0);
      }
      for (const fs::path& path : variants) {
        rp::ImageVolume v;
        std::string error;
        ASSERT_TRUE(Read(path, v, error)) << path << ": " << error;
        for (size_t i = 0; i < raw.size(); ++i)
          ASSERT_EQ(Voxel(v, int(i % Columns), int(i / Columns), 0), expected[i]) << path << " pixel " << i;
      }
    }
  }
  // A truncated 32-bit file is still called truncated.
  const fs::path whole = dir / "unsigned-OW-explicit.dcm", cut = dir / "cut" / "cut.dcm";
  fs::create_directories(cut.parent_path());
  fs::copy_file(whole, cut);
  fs::resize_file(cut, fs::file_size(whole) - 20);
  rp::ImageVolume v;
  std::string error;
  EXPECT_FALSE(Read(cut.parent_path(), v, error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

TEST(DicomPixelValues, FloatAndDoubleFloatPixelDataReadAsFloatVolumes) {
  const fs::path dir = rp::testing::Scratch("float-pixels");
  std::vector<Float32> f(Columns * Rows);
  std::vector<Float64> d(Columns * Rows);
  for (size_t i = 0; i < f.size(); ++i) {
    f[i] = static_cast<Float32>(0.25 * double(i) - 3.1);
    d[i] = 1e-7 * double(i) + 1.0 / 3.0;
  }
  for (const bool isDouble : {false, true}) {
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    Header(ds, "MR", 1, isDouble ? 64 : 32, false, 0, "1.2.826.0.1.3680043.10.1234.5");
    for (const DcmTagKey& tag : {DCM_BitsStored, DCM_HighBit, DCM_PixelRepresentation}) delete ds->remove(tag);
    if (isDouble)
      ASSERT_TRUE(ds->putAndInsertFloat64Array(DCM_DoubleFloatPixelData, d.data(), d.size()).good());
    else
      ASSERT_TRUE(ds->putAndInsertFloat32Array(DCM_FloatPixelData, f.data(), f.size()).good());
    const fs::path path = dir / (isDouble ? "double.dcm" : "float.dcm");
    Save(file, path);
    rp::ImageVolume v;
    std::string error;
    ASSERT_TRUE(Read(path, v, error)) << error;
    EXPECT_EQ(v.Image->GetScalarType(), isDouble ? VTK_DOUBLE : VTK_FLOAT);
    for (size_t i = 0; i < f.size(); ++i)
      ASSERT_EQ(Voxel(v, int(i % Columns), int(i / Columns), 0), isDouble ? d[i] : double(f[i])) << i;
  }
}

TEST(DicomPixelValues, InvalidPixelSpacingIsReadAsOneMillimetreWithAWarning) {
  const fs::path dir = rp::testing::Scratch("zero-spacing");
  for (const std::string spacing : {"0\\0", "-0.5\\0.5", "NaN\\1"}) {
    const fs::path series = dir / std::to_string(std::hash<std::string>()(spacing));
    fs::create_directories(series);
    for (int k = 0; k < 3; ++k) {
      DcmFileFormat file;
      DcmDataset* ds = file.getDataset();
      Header(ds, "CT", 1, 16, true, 2.0 * k, "1.2.826.0.1.3680043.10.1234.6");
      ds->putAndInsertString(DCM_PixelSpacing, spacing.c_str());
      std::vector<Uint16> pixels(Columns * Rows, static_cast<Uint16>(k));
      ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), pixels.size());
      Save(file, series / ("IM" + std::to_string(k) + ".dcm"));
    }
    rp::DicomScanResult scan;
    std::string error;
    ASSERT_TRUE(rp::ScanDicom(series.string(), scan, error)) << error;
    ASSERT_EQ(scan.Series.size(), 1u);
    EXPECT_EQ(scan.Series[0].PixelSpacing[0], 1.0);
    ASSERT_EQ(scan.Series[0].Warnings.size(), 1u) << Join(scan.Series[0].Warnings);
    EXPECT_NE(scan.Series[0].Warnings[0].find("PixelSpacing " + spacing), std::string::npos) << scan.Series[0].Warnings[0];
    EXPECT_NE(scan.Series[0].Warnings[0].find("1 mm pixels assumed"), std::string::npos);
    rp::ImageVolume v;
    std::vector<std::string> warnings;
    ASSERT_TRUE(Read(series, v, error, &warnings)) << error;
    EXPECT_NE(Join(warnings).find("is not a valid spacing: 1 mm pixels assumed"), std::string::npos) << Join(warnings);
    EXPECT_DOUBLE_EQ(std::abs(v.IJKToRAS->GetElement(0, 0)), 1.0);
    EXPECT_DOUBLE_EQ(std::abs(v.IJKToRAS->GetElement(1, 1)), 1.0);
    EXPECT_DOUBLE_EQ(v.IJKToRAS->GetElement(2, 2), 2.0);
  }
}

TEST(DicomPixelValues, PaletteAndColourImagesAreRefusedNamingTheirInterpretation) {
  const fs::path dir = rp::testing::Scratch("colour");
  for (const std::string photometric : {"PALETTE COLOR", "RGB", "YBR_FULL", "YBR_FULL_422"}) {
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    const int samples = photometric == "PALETTE COLOR" ? 1 : 3;
    Header(ds, "OT", 1, 8, false, 0, "1.2.826.0.1.3680043.10.1234.7");
    ds->putAndInsertString(DCM_PhotometricInterpretation, photometric.c_str());
    ds->putAndInsertUint16(DCM_SamplesPerPixel, samples);
    if (samples == 3) ds->putAndInsertUint16(DCM_PlanarConfiguration, 0);
    std::vector<Uint8> pixels(Columns * Rows * samples, 7);
    ds->putAndInsertUint8Array(DCM_PixelData, pixels.data(), pixels.size());
    if (samples == 1) {  // a palette: index 7 is some red
      const Uint16 descriptor[3] = {256, 0, 16};
      std::vector<Uint16> table(256, 0);
      table[7] = 50000;
      for (const auto& tags : {std::make_pair(DCM_RedPaletteColorLookupTableDescriptor, DCM_RedPaletteColorLookupTableData),
                               std::make_pair(DCM_GreenPaletteColorLookupTableDescriptor, DCM_GreenPaletteColorLookupTableData),
                               std::make_pair(DCM_BluePaletteColorLookupTableDescriptor, DCM_BluePaletteColorLookupTableData)}) {
        ds->putAndInsertUint16Array(tags.first, descriptor, 3);
        ds->putAndInsertUint16Array(tags.second, table.data(), table.size());
      }
    }
    const fs::path folder = dir / (photometric == "PALETTE COLOR" ? std::string("palette") : photometric);
    fs::create_directories(folder);
    Save(file, folder / "image.dcm");
    rp::ImageVolume v;
    std::string error;
    EXPECT_FALSE(Read(folder, v, error));
    EXPECT_NE(error.find(photometric), std::string::npos) << error;
    EXPECT_NE(error.find("greyscale"), std::string::npos) << error;
    EXPECT_EQ(v.Image, nullptr);
  }
}

TEST(DicomPixelValues, LegacyMultiFrameMrReadsWithSpacingBetweenSlices) {
  const fs::path dir = rp::testing::Scratch("legacy-multiframe");
  constexpr int frames = 5;
  std::vector<Uint16> pixels(Columns * Rows * frames);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<Uint16>(i);
  auto write = [&](const fs::path& path, const std::string& spacingTag) {
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    Header(ds, "MR", frames, 16, false, 30, "1.2.826.0.1.3680043.10.1234.8");
    // An oblique orientation: frame k sits k * 2.5 mm along row x column from the position.
    ds->putAndInsertString(DCM_ImageOrientationPatient, "0.8\\0.6\\0\\0\\0\\-1");
    if (spacingTag == "SpacingBetweenSlices") ds->putAndInsertString(DCM_SpacingBetweenSlices, "2.5");
    if (spacingTag == "SliceThickness") ds->putAndInsertString(DCM_SliceThickness, "2.5");
    ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), pixels.size());
    fs::create_directories(path.parent_path());
    Save(file, path);
  };
  for (const std::string tag : {"SpacingBetweenSlices", "SliceThickness"}) {
    const fs::path path = dir / tag / "mf.dcm";
    write(path, tag);
    rp::ImageVolume v;
    std::string error;
    std::vector<std::string> warnings;
    ASSERT_TRUE(Read(path, v, error, &warnings)) << error;
    int dims[3];
    v.Image->GetDimensions(dims);
    EXPECT_EQ(dims[2], frames);
    // normal = row x column = (0.8,0.6,0) x (0,0,-1) = (-0.6, 0.8, 0) LPS → RAS (0.6, -0.8, 0).
    EXPECT_NEAR(v.IJKToRAS->GetElement(0, 2), 0.6 * 2.5, 1e-9);
    EXPECT_NEAR(v.IJKToRAS->GetElement(1, 2), -0.8 * 2.5, 1e-9);
    EXPECT_NEAR(v.IJKToRAS->GetElement(0, 3), 10.0, 1e-9);  // LPS -10 → RAS +10
    EXPECT_EQ(Voxel(v, 2, 1, 3), pixels[3 * Columns * Rows + Columns + 2]);
    EXPECT_EQ(Join(warnings).find("SliceThickness") != std::string::npos, tag == "SliceThickness") << Join(warnings);
  }
  {  // Neither spacing: refused, naming what is missing.
    const fs::path path = dir / "none" / "mf.dcm";
    write(path, "");
    rp::ImageVolume v;
    std::string error;
    EXPECT_FALSE(Read(path, v, error));
    EXPECT_NE(error.find("multi-frame image without the geometry of its frames"), std::string::npos) << error;
    EXPECT_NE(error.find("no SpacingBetweenSlices"), std::string::npos) << error;
  }
  {  // Truncated: called truncated, not "multi-frame".
    const fs::path path = dir / "cut" / "mf.dcm";
    write(path, "");
    fs::resize_file(path, fs::file_size(path) - 100);
    rp::ImageVolume v;
    std::string error;
    EXPECT_FALSE(Read(path.parent_path(), v, error));
    EXPECT_NE(error.find("truncated"), std::string::npos) << error;
    EXPECT_EQ(error.find("multi-frame"), std::string::npos) << error;
  }
}

TEST(DicomPixelValues, RtDoseReadsByItsGridFrameOffsetVectorAndDoseGridScaling) {
  const fs::path dir = rp::testing::Scratch("rtdose");
  constexpr int frames = 4;
  std::vector<Uint32> dose(Columns * Rows * frames);
  for (size_t i = 0; i < dose.size(); ++i) dose[i] = static_cast<Uint32>(i * 100003);
  const double scaling = 2.5e-5;
  const double z0 = -42.0;
  // Relative (first offset 0) and absolute (first offset = z of the position), PS3.3 C.8.8.3.2.
  for (const bool absolute : {false, true}) {
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    Header(ds, "RTDOSE", frames, 32, false, z0, "1.2.826.0.1.3680043.10.1234.9");
    ds->putAndInsertString(DCM_DoseGridScaling, "2.5e-5");
    ds->putAndInsertString(DCM_DoseUnits, "GY");
    ds->putAndInsertString(DCM_FrameIncrementPointer, "(3004,000c)");
    const std::string offsets = absolute ? "-42\\-39\\-36\\-33" : "0\\3\\6\\9";
    ds->putAndInsertString(DCM_GridFrameOffsetVector, offsets.c_str());
    ds->putAndInsertUint16Array(DCM_PixelData, reinterpret_cast<Uint16*>(dose.data()), dose.size() * 2);
    const fs::path path = dir / (absolute ? "absolute.dcm" : "relative.dcm");
    Save(file, path, EXS_LittleEndianImplicit);
    rp::ImageVolume v;
    std::string error;
    ASSERT_TRUE(Read(path, v, error)) << error;
    int dims[3];
    v.Image->GetDimensions(dims);
    ASSERT_EQ(dims[2], frames);
    EXPECT_NEAR(v.IJKToRAS->GetElement(2, 2), 3.0, 1e-9);
    EXPECT_NEAR(v.IJKToRAS->GetElement(2, 3), z0, 1e-9);
    for (int k = 0; k < frames; ++k)
      EXPECT_NEAR(Voxel(v, 5, 3, k), dose[(size_t(k) * Rows + 3) * Columns + 5] * scaling, 1e-6 * (1 + Voxel(v, 5, 3, k))) << k;
  }
  {  // Fewer offsets than frames: refused naming the vector.
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    Header(ds, "RTDOSE", frames, 32, false, z0, "1.2.826.0.1.3680043.10.1234.10");
    ds->putAndInsertString(DCM_GridFrameOffsetVector, "0\\3");
    ds->putAndInsertUint16Array(DCM_PixelData, reinterpret_cast<Uint16*>(dose.data()), dose.size() * 2);
    const fs::path path = dir / "short-vector.dcm";
    Save(file, path);
    rp::ImageVolume v;
    std::string error;
    EXPECT_FALSE(Read(path, v, error));
    EXPECT_NE(error.find("GridFrameOffsetVector has fewer than 4 values"), std::string::npos) << error;
  }
}

namespace {

// pydicom's view of a file: its transfer syntax and every pixel value (it reads a Big Endian
// sample most significant byte first, whatever the VR).
const char* const PixelValuesScript = R"PY(
import json, sys
import pydicom
ds = pydicom.dcmread(sys.argv[1])
print(json.dumps({"syntax": str(ds.file_meta.TransferSyntaxUID),
                  "values": [float(v) for v in ds.pixel_array.ravel()]}))
)PY";

// A Big Endian file of `frames` frames: `stored` as the file must hold them, sample by sample,
// most significant byte first. DCMTK swaps OW 16 bits at a time when it writes (each 32-bit
// sample is given high word first so the file gets its bytes in order), writes OB as given,
// and swaps Float (OF) and Double Float (OD) Pixel Data per sample itself.
void WriteBigEndian(const fs::path& path, const std::string& encoding, const std::string& modality, int frames,
                    const std::vector<double>& stored, const std::function<void(DcmDataset*)>& extra) {
  const int bits = encoding == "OB16" ? 16 : encoding == "F64" ? 64 : 32;
  const bool isSigned = std::any_of(stored.begin(), stored.end(), [](double v) { return v < 0; });
  DcmFileFormat file;
  DcmDataset* ds = file.getDataset();
  Header(ds, modality, frames, bits, isSigned, 0, "1.2.826.0.1.3680043.10.1234.20");
  extra(ds);
  if (encoding == "F32" || encoding == "F64") {
    for (const DcmTagKey& tag : {DCM_BitsStored, DCM_HighBit, DCM_PixelRepresentation}) delete ds->remove(tag);
    std::vector<Float32> f(stored.begin(), stored.end());
    if (encoding == "F64")
      ASSERT_TRUE(ds->putAndInsertFloat64Array(DCM_DoubleFloatPixelData, stored.data(), stored.size()).good());
    else
      ASSERT_TRUE(ds->putAndInsertFloat32Array(DCM_FloatPixelData, f.data(), f.size()).good());
  } else if (encoding == "OW32") {
    std::vector<Uint16> words;
    for (double v : stored) {
      const auto u = static_cast<Uint32>(static_cast<int64_t>(v));
      words.insert(words.end(), {static_cast<Uint16>(u >> 16), static_cast<Uint16>(u & 0xffff)});
    }
    ASSERT_TRUE(ds->putAndInsertUint16Array(DCM_PixelData, words.data(), words.size()).good());
  } else {  // OB: the bytes as they lie in the file
    std::vector<Uint8> bytes;
    for (double v : stored) {
      const auto u = static_cast<Uint32>(static_cast<int64_t>(v));
      for (int b = bits / 8 - 1; b >= 0; --b) bytes.push_back(static_cast<Uint8>(u >> (8 * b)));
    }
    ASSERT_TRUE(ds->putAndInsertUint8Array(DCM_PixelData, bytes.data(), bytes.size()).good());
  }
  Save(file, path, EXS_BigEndianExplicit);
}

}  // namespace

// The case of issue 39: a 32-bit RT Dose in Explicit VR Big Endian read with its 16-bit halves
// swapped (a voxel of 1.254 Gy read 577.765). Every sample of a Big Endian file is one number,
// most significant byte first: RT Dose (multi-frame, Dose Grid Scaling, OW), signed and unsigned
// 32-bit in OW and OB, 16-bit OB, Float and Double Float Pixel Data. Each file is checked by
// pydicom (when installed) to hold the values it was written with, then read here exact.
TEST(DicomPixelValues, BigEndianSamplesReadWhole) {
  const fs::path dir = rp::testing::Scratch("big-endian");
  const bool pydicom = rp::testing::HavePydicom();
  constexpr int frames = 3;
  const size_t count = size_t(Columns) * Rows * frames;
  struct Case {
    std::string Name, Encoding, Modality;
    std::function<double(size_t)> Stored;
    double Scale;  // modality value = stored × Scale
  };
  const std::vector<Case> cases = {
      {"rtdose", "OW32", "RTDOSE", [](size_t i) { return double(i == 7 ? 125400 : i * 1000003 % 4000000000u); }, 1e-5},
      {"unsigned-OW", "OW32", "OT", [](size_t i) { return double(i * 150000000 % 4294967295u); }, 1},
      {"signed-OW", "OW32", "OT", [](size_t i) { return (double(i) - 30) * 123457; }, 1},
      {"signed-OB", "OB32", "OT", [](size_t i) { return (double(i) - 40) * 98765; }, 1},
      {"sixteen-OB", "OB16", "OT", [](size_t i) { return double(i * 911 % 65536); }, 1},
      {"float", "F32", "MR", [](size_t i) { return double(static_cast<float>(0.25 * double(i) - 3.1)); }, 1},
      {"double", "F64", "MR", [](size_t i) { return 1e-7 * double(i) + 1.0 / 3.0 - 1e5 * double(i % 3); }, 1},
  };
  for (const Case& c : cases) {
    std::vector<double> stored(count);
    for (size_t i = 0; i < count; ++i) stored[i] = c.Stored(i);
    const fs::path folder = dir / c.Name;
    fs::create_directories(folder);
    const fs::path path = folder / "image.dcm";
    ASSERT_NO_FATAL_FAILURE(WriteBigEndian(path, c.Encoding, c.Modality, frames, stored, [&](DcmDataset* ds) {
      ds->putAndInsertString(DCM_SpacingBetweenSlices, "2");
      if (c.Modality == "RTDOSE") {
        ds->putAndInsertString(DCM_DoseGridScaling, "1e-5");
        ds->putAndInsertString(DCM_DoseUnits, "GY");
        ds->putAndInsertString(DCM_FrameIncrementPointer, "(3004,000c)");
        ds->putAndInsertString(DCM_GridFrameOffsetVector, "0\\2\\4");
      }
    }));
    if (pydicom) {  // the independent reader sees the values the file was written with
      ASSERT_EQ(rp::testing::RunPython(PixelValuesScript, folder, {path.string()}), 0)
          << rp::testing::Slurp(folder / "python.log");
      const nlohmann::json seen = nlohmann::json::parse(rp::testing::Slurp(folder / "python.out"));
      EXPECT_EQ(seen["syntax"], "1.2.840.10008.1.2.2") << c.Name;
      ASSERT_EQ(seen["values"].size(), count) << c.Name;
      for (size_t i = 0; i < count; ++i) ASSERT_EQ(seen["values"][i].get<double>(), stored[i]) << c.Name << " " << i;
    }
    rp::ImageVolume v;
    std::string error;
    ASSERT_TRUE(Read(folder, v, error)) << c.Name << ": " << error;
    int dims[3];
    v.Image->GetDimensions(dims);
    ASSERT_EQ(dims[2], frames) << c.Name;
    for (size_t i = 0; i < count; ++i) {
      const double expected = stored[i] * c.Scale;
      const int x = int(i % Columns), y = int(i / Columns % Rows), k = int(i / (size_t(Columns) * Rows));
      // Scaled doses are float voxels (7 digits); the rest exact.
      const double tolerance = (c.Scale == 1 ? 1e-9 : 1e-6) * (1 + std::abs(expected));
      ASSERT_NEAR(Voxel(v, x, y, k), expected, tolerance) << c.Name << " pixel " << i;
    }
    if (c.Modality == "RTDOSE") {
      EXPECT_NEAR(Voxel(v, 1, 1, 0), 1.254, 1e-6);  // stored 125400 × 1e-5 Gy
    }
  }
}
