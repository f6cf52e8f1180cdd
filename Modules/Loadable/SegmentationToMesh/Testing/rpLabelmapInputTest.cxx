// Labelmaps from other tools in `roboplan mesh`: a hand-written LPS NRRD (as ITK-SNAP/Slicer write
// them: int16, anisotropic, off-origin) meshes per label to the analytic spheres it was rasterized
// from; label tables in Slicer's and ITK-SNAP's formats; the labelmap-vs-intensity decision and its
// message; fractional threshold bounds on integer images round inward.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpAnalyticSolids.h"
#include "rpLabelTable.h"
#include "rpLabelmapInput.h"
#include "rpLabelmapToMesh.h"
#include "rpMeshCommand.h"
#include "rpModelIO.h"
#include "rpSurfaceError.h"
#include "rpTestOutput.h"
#include "rpVolumeIO.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

fs::path TestDir(const std::string& name) { return rptest::TestDir("labelmap-input/" + name); }

struct MeshRun {
  int Code = -1;
  std::string Out, Err;
  json Doc;
};

MeshRun Mesh(const std::string& args) {
  std::istringstream in(args);
  std::vector<std::string> arguments;
  for (std::string a; in >> a;) arguments.push_back(a);
  std::ostringstream out, err;
  MeshRun run;
  run.Code = rp::RunMeshCommand(arguments, nullptr, out, err);
  run.Out = out.str();
  run.Err = err.str();
  run.Doc = json::parse(run.Out, nullptr, false);
  return run;
}

// LPS grid of the test labelmaps: 0.7 x 0.8 x 1.5 mm voxels, origin far from 0.
constexpr int Dims[3] = {56, 52, 26};
constexpr double Spacing[3] = {0.7, 0.8, 1.5};
constexpr double OriginLPS[3] = {-52.3, 31.7, 80.2};

struct Ball {
  double CenterLPS[3];
  double Radius;
  short Label;
};
const Ball Balls[] = {{{-33.1, 52.4, 99.6}, 12.0, 1}, {{-18.2, 42.9, 91.3}, 5.0, 7}};

// A voxel is inside a ball when its centre is (the rasterization the truth is compared with).
std::vector<short> Rasterize() {
  std::vector<short> voxels(static_cast<size_t>(Dims[0]) * Dims[1] * Dims[2], 0);
  for (int k = 0; k < Dims[2]; ++k)
    for (int j = 0; j < Dims[1]; ++j)
      for (int i = 0; i < Dims[0]; ++i) {
        const double p[3] = {OriginLPS[0] + i * Spacing[0], OriginLPS[1] + j * Spacing[1], OriginLPS[2] + k * Spacing[2]};
        for (const Ball& b : Balls) {
          const double dx = p[0] - b.CenterLPS[0], dy = p[1] - b.CenterLPS[1], dz = p[2] - b.CenterLPS[2];
          if (dx * dx + dy * dy + dz * dz < b.Radius * b.Radius)
            voxels[(static_cast<size_t>(k) * Dims[1] + j) * Dims[0] + i] = b.Label;
        }
      }
  return voxels;
}

// The NRRD as Slicer and ITK-SNAP write a labelmap (written here by hand, not by our writer).
void WriteNrrd(const fs::path& path, const std::vector<short>& voxels) {
  std::ofstream f(path, std::ios::binary);
  f << "NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\n"
    << "sizes: " << Dims[0] << " " << Dims[1] << " " << Dims[2] << "\n"
    << "space directions: (" << Spacing[0] << ",0,0) (0," << Spacing[1] << ",0) (0,0," << Spacing[2] << ")\n"
    << "kinds: domain domain domain\nendian: little\nencoding: raw\n"
    << "space origin: (" << OriginLPS[0] << "," << OriginLPS[1] << "," << OriginLPS[2] << ")\n\n";
  f.write(reinterpret_cast<const char*>(voxels.data()), static_cast<std::streamsize>(voxels.size() * sizeof(short)));
}

void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(LabelmapInput, SphereLabelmapMeshesToTheAnalyticSphere) {
  const fs::path dir = TestDir("spheres");
  const fs::path file = dir / "balls-label.nrrd";
  WriteNrrd(file, Rasterize());
  WriteText(dir / "balls.ctbl", "# Slicer colour table\n0 Background 0 0 0 0\n1 femur 230 220 170 255\n"
                                "7 Tumour 255 0 0 255\n9 unused 0 255 0 255\n");
  const MeshRun run = Mesh(file.string() + " --out " + (dir / "out").string() + " --labels " +
                       (dir / "balls.ctbl").string() + " --no-haptic --json");
  ASSERT_EQ(run.Code, 0) << run.Err;
  ASSERT_TRUE(run.Doc.is_object()) << run.Out;
  EXPECT_EQ(run.Doc["inputKind"]["kind"], "labelmap");
  EXPECT_NE(run.Doc["inputKind"]["reason"].get<std::string>().find("2 label values"), std::string::npos)
      << run.Doc["inputKind"];
  ASSERT_EQ(run.Doc["segments"].size(), 2u);
  EXPECT_EQ(run.Doc["segments"][0]["name"], "femur");
  EXPECT_EQ(run.Doc["segments"][0]["labelValue"], 1);
  EXPECT_EQ(run.Doc["segments"][1]["name"], "Tumour");
  EXPECT_EQ(run.Doc["segments"][1]["labelValue"], 7);

  for (size_t n = 0; n < 2; ++n) {
    const Ball& b = Balls[n];
    const auto& display = run.Doc["segments"][n]["display"];
    EXPECT_TRUE(display["watertight"].get<bool>());
    vtkNew<vtkPolyData> mesh;
    std::string error;
    ASSERT_TRUE(rp::ReadModelFile(display["file"].get<std::string>(), mesh, error)) << error;
    // The truth in RAS (the file is LPS).
    const std::array<double, 3> center = {-b.CenterLPS[0], -b.CenterLPS[1], b.CenterLPS[2]};
    const rp::test::AnalyticSolid sphere = rp::test::Sphere(center, b.Radius);
    double volume = 0, area = 0;
    rp::MeshVolumeAndArea(mesh, volume, area);
    const rp::SurfaceError e = rp::CompareToSurface(mesh, sphere.SDF, sphere.SurfacePoints);
    const double volumeError = 100 * (volume - sphere.Volume) / sphere.Volume;
    std::printf("ball R=%.0f mm: volume error %+.3f %%, mean distance %.3f mm, hausdorff %.3f mm\n", b.Radius,
                volumeError, e.MeanMm, e.HausdorffMm);
    if (n == 0) {  // the done-when figure (a 12 mm ball on 0.7 x 0.8 x 1.5 mm voxels)
      EXPECT_LT(std::abs(volumeError), 1.0);
      EXPECT_LT(e.MeanMm, 0.1);
    } else {  // 5 mm: a handful of 1.5 mm slices
      EXPECT_LT(std::abs(volumeError), 3.0);
      EXPECT_LT(e.MeanMm, 0.2);
    }
  }
}

TEST(LabelmapInput, LabelTablesOfSlicerAndItkSnap) {
  const fs::path dir = TestDir("tables");
  WriteText(dir / "snap.txt",
            "################################################\n# ITK-SnAP Label Description File\n"
            "# IDX   -R-  -G-  -B-  -A--  VIS MSH  LABEL\n"
            "    0     0    0    0        0  0  0    \"Clear Label\"\n"
            "    1   255    0    0        1  1  1    \"Left femur\"\n"
            "   12     0  128  255     0.50  1  1    \"Tibia (proximal)\"\n");
  rp::LabelTable table;
  std::string error;
  ASSERT_TRUE(rp::ReadLabelTable((dir / "snap.txt").string(), table, error)) << error;
  ASSERT_EQ(table.Entries.size(), 3u);
  ASSERT_NE(table.Find(12), nullptr);
  EXPECT_EQ(table.Find(12)->Name, "Tibia (proximal)");
  EXPECT_NEAR(table.Find(12)->Color[2], 1.0, 1e-12);
  EXPECT_NEAR(table.Find(12)->Color[1], 128 / 255.0, 1e-12);
  EXPECT_EQ(table.Find(1)->Name, "Left femur");
  EXPECT_EQ(table.Find(2), nullptr);

  WriteText(dir / "slicer.txt", "# comment\n0 Background 0 0 0 0\r\n3 patella 10 20 30 255\r\n");
  ASSERT_TRUE(rp::ReadLabelTable((dir / "slicer.txt").string(), table, error)) << error;
  EXPECT_EQ(table.Find(3)->Name, "patella");
  EXPECT_NEAR(table.Find(3)->Color[0], 10 / 255.0, 1e-12);

  // Malformed files name the file and the line.
  WriteText(dir / "bad.txt", "0 Background 0 0 0 0\n1 femur red 0 0 255\n");
  EXPECT_FALSE(rp::ReadLabelTable((dir / "bad.txt").string(), table, error));
  EXPECT_NE(error.find("line 2"), std::string::npos) << error;
  EXPECT_NE(error.find("red"), std::string::npos) << error;
  WriteText(dir / "twice.txt", "1 a 0 0 0 255\n1 b 0 0 0 255\n");
  EXPECT_FALSE(rp::ReadLabelTable((dir / "twice.txt").string(), table, error));
  EXPECT_NE(error.find("twice"), std::string::npos) << error;
  WriteText(dir / "empty.txt", "# nothing\n");
  EXPECT_FALSE(rp::ReadLabelTable((dir / "empty.txt").string(), table, error));
  EXPECT_FALSE(rp::ReadLabelTable((dir / "missing.txt").string(), table, error));
  EXPECT_NE(error.find("missing.txt"), std::string::npos);
}

TEST(LabelmapInput, AutoDecisionIsExplainedAndCanBeForced) {
  const fs::path dir = TestDir("auto");
  const auto voxels = Rasterize();
  // A name that says nothing and no table: taken as intensity, and the output says how to ask.
  const fs::path plain = dir / "case001.nrrd";
  WriteNrrd(plain, voxels);
  MeshRun run = Mesh(plain.string() + " --out " + (dir / "a").string() + " --no-haptic --json");
  EXPECT_EQ(run.Doc["inputKind"]["kind"], "intensity") << run.Out << run.Err;
  EXPECT_NE(run.Doc["inputKind"]["reason"].get<std::string>().find("--input-kind labelmap"), std::string::npos);
  EXPECT_NE(run.Err.find("if it is a labelmap, say --input-kind labelmap"), std::string::npos) << run.Err;  // --json too
  // Forced: one segment per label, default names.
  run = Mesh(plain.string() + " --out " + (dir / "b").string() + " --input-kind labelmap --no-haptic --json");
  ASSERT_EQ(run.Code, 0) << run.Err;
  EXPECT_EQ(run.Doc["inputKind"]["kind"], "labelmap");
  ASSERT_EQ(run.Doc["segments"].size(), 2u);
  EXPECT_EQ(run.Doc["segments"][0]["name"], "Label 1");
  EXPECT_EQ(run.Doc["segments"][1]["name"], "Label 7");
  // Text mode says the choice on stderr.
  run = Mesh(plain.string() + " --out " + (dir / "c").string() + " --input-kind labelmap --no-haptic");
  EXPECT_NE(run.Err.find("input: labelmap (--input-kind labelmap)"), std::string::npos) << run.Err;
  // A threshold option means intensity even for a labelmap-named file.
  const fs::path named = dir / "case001_label.nrrd";
  WriteNrrd(named, voxels);
  run = Mesh(named.string() + " --out " + (dir / "d").string() + " --lower 6.5 --upper 7.5 --no-haptic --json");
  ASSERT_EQ(run.Code, 0) << run.Err;
  EXPECT_EQ(run.Doc["inputKind"]["kind"], "intensity");
  // --labels with an intensity image is a contradiction.
  WriteText(dir / "t.txt", "1 a 1 1 1 255\n");
  run = Mesh(named.string() + " --out " + (dir / "e").string() + " --input-kind intensity --labels " +
             (dir / "t.txt").string());
  EXPECT_EQ(run.Code, 2);
  EXPECT_NE(run.Err.find("--labels"), std::string::npos) << run.Err;
  run = Mesh(named.string() + " --out " + (dir / "e").string() + " --input-kind maybe");
  EXPECT_EQ(run.Code, 2);
  EXPECT_NE(run.Err.find("maybe"), std::string::npos) << run.Err;

  // A CT-like image (many values, negative) is never a labelmap, and a forced one is refused.
  vtkNew<vtkImageData> ct;
  ct->SetDimensions(20, 20, 20);
  ct->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(ct->GetScalarPointer());
  for (int n = 0; n < 8000; ++n) v[n] = static_cast<short>(n % 3000 - 1000);
  vtkNew<vtkMatrix4x4> identity;
  EXPECT_FALSE(rp::ChooseInputKind(rp::InputKind::Auto, ct, "ct-label.nrrd", true, false).Labelmap);
  const fs::path ctFile = dir / "ct-label.nrrd";
  std::string error;
  ASSERT_TRUE(rp::WriteVolumeFile(ctFile.string(), ct, identity, {}, error)) << error;
  run = Mesh(ctFile.string() + " --out " + (dir / "f").string() + " --input-kind labelmap");
  EXPECT_EQ(run.Code, 1);
  EXPECT_NE(run.Err.find("not a labelmap"), std::string::npos) << run.Err;
}

TEST(LabelmapInput, FloatLabelmapsOfWholeNumbersAreConverted) {
  // Some tools write labelmaps as float: whole numbers are accepted, fractions refused.
  vtkNew<vtkImageData> image;
  image->SetDimensions(8, 8, 8);
  image->AllocateScalars(VTK_FLOAT, 1);
  auto* v = static_cast<float*>(image->GetScalarPointer());
  for (int n = 0; n < 512; ++n) v[n] = n < 100 ? 0.0f : (n < 300 ? 2.0f : 300.0f);
  vtkNew<vtkMatrix4x4> identity;
  vtkNew<vtkRPSegmentationNode> segmentation;
  std::string error;
  ASSERT_TRUE(rp::LabelmapToSegmentation(image, identity, nullptr, segmentation, error)) << error;
  EXPECT_EQ(segmentation->GetImageData()->GetScalarType(), VTK_UNSIGNED_SHORT);
  ASSERT_EQ(segmentation->GetNumberOfSegments(), 2);
  EXPECT_EQ(segmentation->GetNthSegment(1).LabelValue, 300);
  v[7] = 0.5f;
  EXPECT_FALSE(rp::LabelmapToSegmentation(image, identity, nullptr, segmentation, error));
  EXPECT_NE(error.find("fractional"), std::string::npos) << error;
  EXPECT_EQ(segmentation->GetNumberOfSegments(), 2) << "left untouched on failure";
  v[7] = -1.0f;
  EXPECT_FALSE(rp::LabelmapToSegmentation(image, identity, nullptr, segmentation, error));
  EXPECT_NE(error.find("negative"), std::string::npos) << error;
}

TEST(LabelmapInput, FractionalBoundsOnIntegerImagesRoundInward) {
  const fs::path dir = TestDir("fractional");
  const fs::path file = dir / "balls.nrrd";
  const auto voxels = Rasterize();
  WriteNrrd(file, voxels);
  long ones = 0;
  for (short v : voxels) ones += v == 1;
  // [0.9, 1.1] on integers selects 1 only (it used to truncate to [0, 1]: the whole volume).
  MeshRun run = Mesh(file.string() + " --out " + (dir / "a").string() +
                 " --input-kind intensity --lower 0.9 --upper 1.1 --no-haptic --json");
  ASSERT_EQ(run.Code, 0) << run.Err;
  EXPECT_EQ(run.Doc["segmentation"][0]["voxels"].get<long>(), ones);
  // [0.4, 0.6] holds no whole number: refused rather than rounded to an empty or a full range.
  run = Mesh(file.string() + " --out " + (dir / "b").string() +
             " --input-kind intensity --lower 0.4 --upper 0.6 --no-haptic");
  EXPECT_EQ(run.Code, 1);
  EXPECT_NE(run.Err.find("no whole number"), std::string::npos) << run.Err;
}

TEST(LabelmapInput, ValueCountsMatchAVoxelByVoxelCount) {
  // Runs of one value (counted 16 voxels at a time), noise between them, a tail shorter than a
  // block; 8-bit and signed 16-bit voxels.
  auto check = [](int type, auto sample) {
    using T = decltype(sample);
    vtkNew<vtkImageData> image;
    image->SetDimensions(101, 37, 23);  // not a multiple of 16
    image->AllocateScalars(type, 1);
    auto* v = static_cast<T*>(image->GetScalarPointer());
    const vtkIdType n = image->GetNumberOfPoints();
    std::map<long, long> expected;
    for (vtkIdType i = 0; i < n; ++i) {
      const bool run = (i / 200) % 3 != 0;
      v[i] = static_cast<T>(run ? (i / 600) % 4 : static_cast<long>((i * 7919) % 251) - (sizeof(T) > 1 ? 100 : 0));
      ++expected[static_cast<long>(v[i])];
    }
    const rp::ImageValues values = rp::CollectImageValues(image, 10000);
    ASSERT_EQ(values.Values.size(), expected.size());
    size_t k = 0;
    for (const auto& [value, count] : expected) {
      EXPECT_EQ(values.Values[k], value);
      EXPECT_EQ(values.Counts[k], count) << "value " << value;
      ++k;
    }
    EXPECT_EQ(values.Min, static_cast<double>(expected.begin()->first));
    EXPECT_EQ(values.Max, static_cast<double>(expected.rbegin()->first));
  };
  check(VTK_UNSIGNED_CHAR, static_cast<unsigned char>(0));
  check(VTK_SHORT, static_cast<short>(0));
}
