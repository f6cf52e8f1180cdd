// Every transfer syntax a PACS sends, on real series from other writers (shared/data): each
// case re-encodes the files AT TEST TIME with the packages' own tools (gdcmconv from
// libgdcm-tools; dcmcjpeg, dcmcjpls, dcmcrle, dcmconv from dcmtk), reads the result with our
// reader and compares it with the original: lossless syntaxes voxel-identical, lossy ones
// within the codec's stated error, geometry identical. A missing tool skips with its name.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <sstream>

#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomSeries.h"
#include "rpDicomTestTools.h"
#include "rpDicomTransferSyntax.h"
#include "rpSharedData.h"

namespace fs = std::filesystem;
using rp::testing::FindTool;
using rp::testing::Scratch;

namespace {

const std::string kData = ROBOPLAN_SHARED_DATA_DIR;

// A real series (or its first files) copied as is: the reference every encoding is compared with.
struct Source {
  std::string Name, Folder;
  size_t MaxFiles;
};
const Source kSources[] = {
    {"ge-ct", "dicom/ct-3slice", 3},        // GE CT, implicit VR, int16 + intercept
    {"knee-ct", "knee-ct-vhf/dicom", 5},    // Visible Human knee CT, explicit VR
    {"pacsman-mr", "dicom/pacsman-mr", 5},  // third-party MR writer, rotated in-plane axes
};

// An encoder and what its output must satisfy.
struct Codec : rp::testing::DicomEncoder {
  enum Kind { Lossless, MaxDeviation, Psnr, Jpeg } Check = Lossless;
  double Bound = 0.0;  // MaxDeviation: stored-value deviation; Psnr, Jpeg: dB
};

void PrintTo(const Codec& codec, std::ostream* out) { *out << codec.Name; }

std::vector<Codec> Codecs() {
  const std::map<std::string, std::pair<Codec::Kind, double>> checks = {
      {"jpeg-baseline", {Codec::Jpeg, 30}},          {"jpeg-extended", {Codec::Jpeg, 30}},
      {"jpegls-near-dcmcjpls", {Codec::MaxDeviation, 2}}, {"jpegls-near-gdcm", {Codec::MaxDeviation, 3}},
      {"j2k-lossy", {Codec::Psnr, 80}}};
  std::vector<Codec> codecs;
  for (const rp::testing::DicomEncoder& e : rp::testing::DicomEncoders()) {
    Codec c;
    static_cast<rp::testing::DicomEncoder&>(c) = e;
    if (auto it = checks.find(e.Name); it != checks.end()) std::tie(c.Check, c.Bound) = it->second;
    codecs.push_back(c);
  }
  return codecs;
}

std::vector<fs::path> SeriesFiles(const Source& source) {
  return rp::testing::DicomFiles(kData + "/" + source.Folder, source.MaxFiles);
}

std::string TransferSyntaxOf(const fs::path& file) {
  rp::DicomScanResult scan;
  std::string error;
  if (!rp::ScanDicom(file.string(), scan, error) || scan.Series.empty()) return "(unreadable: " + error + ")";
  return scan.Series[0].TransferSyntaxUID;
}

double Value(vtkDataArray* a, vtkIdType i) { return a->GetComponent(i, 0); }

class TransferSyntax : public ::testing::TestWithParam<Codec> {};

TEST_P(TransferSyntax, RealSeriesReadBackAsEncoded) {
  const Codec& codec = GetParam();
  const std::string tool = FindTool(codec.Tool);
  if (tool.empty()) GTEST_SKIP() << codec.Tool << " not found on PATH (Debian package " << codec.Package << ")";
  for (const Source& source : kSources) RP_REQUIRE_SHARED_DATA(source.Folder);
  const fs::path root = Scratch(codec.Name);
  const std::string dcmodify = FindTool("dcmodify");
  if (!codec.Prepare.empty() && dcmodify.empty()) GTEST_SKIP() << "dcmodify not found on PATH (Debian package dcmtk)";
  for (const Source& source : kSources) {
    if (!codec.OnlySource.empty() && codec.OnlySource != source.Name) continue;
    SCOPED_TRACE(source.Name);
    const fs::path original = root / "original" / source.Name, encoded = root / source.Name;
    fs::create_directories(original);
    fs::create_directories(encoded);
    for (const fs::path& file : SeriesFiles(source)) {
      fs::copy_file(file, original / file.filename());
      const std::string log = " >>\"" + (root / "tool.log").string() + "\" 2>&1";
      if (!codec.Prepare.empty()) {
        const std::string prepare =
            "\"" + dcmodify + "\" " + codec.Prepare + " \"" + (original / file.filename()).string() + "\"" + log;
        ASSERT_EQ(std::system(prepare.c_str()), 0) << prepare;
      }
      const fs::path input = original / file.filename();
      ASSERT_EQ(rp::testing::Encode(codec, tool, input.string(), (encoded / file.filename()).string(),
                                    (root / "tool.log").string()),
                0)
          << codec.Tool << " " << codec.Arguments << " " << input << " (see " << (root / "tool.log") << ")";
      ASSERT_EQ(TransferSyntaxOf(encoded / file.filename()), codec.TransferSyntaxUID) << codec.Name;
    }
    rp::ImageVolume reference, decoded;
    std::string error;
    std::vector<std::string> warnings;
    ASSERT_TRUE(rp::ReadDicomVolume(original.string(), reference, error)) << error;
    ASSERT_TRUE(rp::ReadDicomVolume(encoded.string(), decoded, error, "", {}, &warnings)) << error;
    int dr[3], dd[3];
    reference.Image->GetDimensions(dr);
    decoded.Image->GetDimensions(dd);
    ASSERT_EQ(std::vector<int>(dr, dr + 3), std::vector<int>(dd, dd + 3));
    // Geometry identical: the tools copy the headers' decimal strings.
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(decoded.IJKToRAS->GetElement(r, c), reference.IJKToRAS->GetElement(r, c), 1e-9) << r << "," << c;
    vtkDataArray* a = reference.Image->GetPointData()->GetScalars();
    vtkDataArray* b = decoded.Image->GetPointData()->GetScalars();
    double maxError = 0.0, sumSquares = 0.0, lo = 1e300, hi = -1e300;
    const vtkIdType n = a->GetNumberOfTuples();
    for (vtkIdType i = 0; i < n; ++i) {
      const double e = Value(b, i) - Value(a, i);
      maxError = std::max(maxError, std::abs(e));
      sumSquares += e * e;
      lo = std::min(lo, Value(a, i));
      hi = std::max(hi, Value(a, i));
    }
    const double rms = std::sqrt(sumSquares / n);
    std::cout << "[ " << codec.Name << " / " << source.Name << " ] max |error| " << maxError << ", RMS " << rms
              << " (range " << lo << ".." << hi << ")\n";
    const rp::TransferSyntaxInfo* syntax = rp::FindTransferSyntax(codec.TransferSyntaxUID);
    ASSERT_NE(syntax, nullptr);
    EXPECT_EQ(syntax->Lossless, codec.Check == Codec::Lossless) << "the syntax table disagrees with the tool";
    const bool warned = std::any_of(warnings.begin(), warnings.end(),
                                    [](const std::string& w) { return w.find("lossy") != std::string::npos; });
    EXPECT_EQ(warned, !syntax->Lossless);
    switch (codec.Check) {
      case Codec::Lossless:
        EXPECT_EQ(maxError, 0.0);
        break;
      case Codec::MaxDeviation:
        // JPEG-LS near-lossless guarantees |error| <= NEAR on every stored value (slope 1 here).
        EXPECT_LE(maxError, codec.Bound);
        EXPECT_GT(maxError, 0.0) << "near-lossless encoding left every voxel unchanged: not exercised";
        break;
      case Codec::Psnr: {
        // OpenJPEG's fixed-quality mode targets a PSNR against the stored range 2^bits - 1.
        const double peak = 65535.0;
        const double psnr = rms > 0 ? 20.0 * std::log10(peak / rms) : 999.0;
        std::cout << "    PSNR " << psnr << " dB (target " << codec.Bound << " dB)\n";
        EXPECT_GE(psnr, codec.Bound - 1.0);
        EXPECT_GT(maxError, 0.0) << "lossy JPEG 2000 left every voxel unchanged: not exercised";
        break;
      }
      case Codec::Jpeg: {
        // DCT JPEG has no error bound (IJG quality 90 is not one): DCMTK maps the values onto 8
        // (baseline) or 12 (extended) bits with a new rescale, then quantizes the DCT. Required:
        // a PSNR against the image's own range of at least codec.Bound dB ("visually
        // acceptable"), and that the codec did lose something (so the path is exercised).
        const double psnr = rms > 0 ? 20.0 * std::log10((hi - lo) / rms) : 999.0;
        std::cout << "    PSNR " << psnr << " dB against the range (floor " << codec.Bound << " dB)\n";
        EXPECT_GE(psnr, codec.Bound);
        EXPECT_GT(maxError, 0.0) << "lossy JPEG left every voxel unchanged: not exercised";
        break;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RealSeries, TransferSyntax, ::testing::ValuesIn(Codecs()),
                         [](const ::testing::TestParamInfo<Codec>& info) {
                           std::string name = info.param.Name;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// DCMTK's CharLS 1 fork and CharLS 2 export JpegLsDecode & co. under the same names; the reader
// decodes JPEG-LS through CharLS 2's charls_jpegls_decoder_* API, which only CharLS 2 has. Load
// DCMTK's fork into this process first (as any target linking ${ITK_LIBRARIES} does when the
// linker keeps every library, e.g. under the sanitizers): JPEG-LS lossless and near-lossless must
// still read correctly, JPEG 2000 must agree with GDCM's own API, and a damaged JPEG-LS
// codestream must be an error naming the file.
TEST(TransferSyntaxLibraries, JpegLsIsRightWhicheverCharLSIsLoaded) {
  const std::string gdcmconv = FindTool("gdcmconv");
  if (gdcmconv.empty()) GTEST_SKIP() << "gdcmconv not found on PATH (Debian package libgdcm-tools)";
  RP_REQUIRE_SHARED_DATA("dicom/ct-3slice/02.dcm");
  const fs::path source = kData + "/dicom/ct-3slice/02.dcm";
  void* dcmtkCharLS = dlopen("libdcmtkcharls.so.17", RTLD_NOW | RTLD_GLOBAL);
  Dl_info info{};
  if (void* symbol = dlsym(RTLD_DEFAULT, "JpegLsDecode"); symbol && dladdr(symbol, &info))
    std::cout << "JpegLsDecode resolves to " << info.dli_fname << " in this process\n";
  const fs::path root = Scratch("libraries");
  rp::ImageVolume original;
  std::string error;
  ASSERT_TRUE(rp::ReadDicomVolume(source.string(), original, error)) << error;
  vtkDataArray* a = original.Image->GetPointData()->GetScalars();
  for (const std::string& args : {std::string("--jpegls"), std::string("--jpegls --lossy -e 2"),
                                  std::string("--j2k")}) {
    SCOPED_TRACE(args);
    const fs::path out = root / "encoded.dcm";
    fs::remove(out);
    const std::string command =
        "\"" + gdcmconv + "\" " + args + " \"" + source.string() + "\" \"" + out.string() + "\" >/dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    rp::ImageVolume ours;
    ASSERT_TRUE(rp::ReadDicomVolume(out.string(), ours, error)) << error;
    vtkDataArray* b = ours.Image->GetPointData()->GetScalars();
    double maxOurs = 0;
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
      maxOurs = std::max(maxOurs, std::abs(b->GetComponent(i, 0) - a->GetComponent(i, 0)));
    EXPECT_LE(maxOurs, args.find("-e 2") != std::string::npos ? 2.0 : 0.0);
    if (args == "--j2k") {  // GDCM's own API on the same file (OpenJPEG: no clash)
      gdcm::ImageReader reader;
      reader.SetFileName(out.c_str());
      ASSERT_TRUE(reader.Read());
      std::vector<char> buffer(reader.GetImage().GetBufferLength());
      ASSERT_TRUE(reader.GetImage().GetBuffer(buffer.data()));
      ASSERT_EQ(buffer.size(), size_t(512 * 512 * 2));
      const int16_t* theirs = reinterpret_cast<const int16_t*>(buffer.data());
      double maxBetween = 0;
      for (vtkIdType i = 0; i < b->GetNumberOfTuples(); ++i)
        maxBetween = std::max(maxBetween, std::abs(theirs[i] - 1024.0 - b->GetComponent(i, 0)));  // intercept -1024
      EXPECT_EQ(maxBetween, 0.0);
    }
  }
  // A damaged JPEG-LS codestream is an error naming the file, not a crash.
  const fs::path damaged = root / "damaged.dcm";
  ASSERT_EQ(std::system(("\"" + gdcmconv + "\" --jpegls \"" + source.string() + "\" \"" + damaged.string() +
                         "\" >/dev/null 2>&1")
                            .c_str()),
            0);
  {
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-4000, std::ios::end);
    const std::string garbage(2000, '\xff');
    f.write(garbage.data(), garbage.size());
  }
  rp::ImageVolume v;
  EXPECT_FALSE(rp::ReadDicomVolume(damaged.string(), v, error));
  EXPECT_NE(error.find("damaged.dcm"), std::string::npos) << error;
  std::cout << "damaged JPEG-LS: " << error << "\n";
  if (dcmtkCharLS) dlclose(dcmtkCharLS);
}

}  // namespace
