// Volumes that cannot fit are refused from their header, before anything is allocated: the
// message names the size and the memory it would need; no std::bad_alloc, no VTK error line.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkStringOutputWindow.h>

#include "rpSegmentationIO.h"
#include "rpVolumeIO.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace {

fs::path Dir() {
  const fs::path d = fs::path(ROBOPLAN_TEST_OUTPUT_DIR);
  fs::create_directories(d);
  return d;
}

// Reads `path` as a volume with VTK's messages captured; expects a refusal naming `needle`.
void ExpectRefused(const fs::path& path, const std::string& needle) {
  vtkNew<vtkStringOutputWindow> messages;
  vtkOutputWindow::SetInstance(messages);
  vtkNew<vtkImageData> image;
  vtkNew<vtkMatrix4x4> ijkToRAS;
  rp::VolumeFileData data;
  data.Image = image;
  data.IJKToRAS = ijkToRAS;
  std::string error;
  EXPECT_FALSE(rp::ReadVolumeFile(path.string(), data, error));
  EXPECT_NE(error.find(needle), std::string::npos) << error;
  EXPECT_NE(error.find(path.filename().string()), std::string::npos) << error;
  EXPECT_EQ(image->GetNumberOfPoints(), 0);
  EXPECT_EQ(messages->GetOutput(), "") << "VTK logged while refusing";
  vtkOutputWindow::SetInstance(nullptr);
}

}  // namespace

TEST(VolumeSizeRefusal, NrrdHeaderOfTenToTheFifteenVoxels) {
  const fs::path path = Dir() / "huge.nrrd";
  std::ofstream(path) << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 100000\n"
                         "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                         "space origin: (0,0,0)\nencoding: raw\n\n";
  ExpectRefused(path, "100000 x 100000 x 100000 voxels of 1 byte would need 1e+06 GB");
}

TEST(VolumeSizeRefusal, MetaImageAndNiftiHeaders) {
  const fs::path mha = Dir() / "huge.mha";
  std::ofstream(mha) << "ObjectType = Image\nNDims = 3\nDimSize = 50000 50000 4000\nElementType = MET_SHORT\n"
                        "ElementDataFile = LOCAL\n";
  ExpectRefused(mha, "50000 x 50000 x 4000 voxels of 2 bytes would need 2e+04 GB");

  // A real small NIfTI written by ITK, its dim[1..3] (int16 at byte 42) then raised to 30000.
  const fs::path nii = Dir() / "huge.nii";
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 4, 4);
  image->AllocateScalars(VTK_FLOAT, 1);
  vtkNew<vtkMatrix4x4> identity;
  std::string error;
  ASSERT_TRUE(rp::WriteVolumeFile(nii.string(), image, identity, {}, error, false)) << error;
  {
    std::fstream f(nii, std::ios::in | std::ios::out | std::ios::binary);
    const int16_t dims[3] = {30000, 30000, 30000};
    f.seekp(42);
    f.write(reinterpret_cast<const char*>(dims), sizeof dims);
  }
  ExpectRefused(nii, "30000 x 30000 x 30000 voxels of 4 bytes would need 1.08e+05 GB");
}

TEST(VolumeSizeRefusal, SegmentationHeader) {
  const fs::path path = Dir() / "huge.seg.nrrd";
  std::ofstream(path) << "NRRD0004\ntype: short\ndimension: 3\nsizes: 20000 20000 20000\nendian: little\n"
                         "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                         "space origin: (0,0,0)\nencoding: raw\nSegment0_ID:=a\nSegment0_LabelValue:=1\n\n";
  vtkNew<vtkStringOutputWindow> messages;
  vtkOutputWindow::SetInstance(messages);
  vtkNew<vtkRPSegmentationNode> node;
  std::string error;
  EXPECT_FALSE(rp::ReadSegmentationFile(path.string(), node, error));
  EXPECT_NE(error.find("20000 x 20000 x 20000 voxels of 2 bytes would need 1.6e+04 GB"), std::string::npos) << error;
  EXPECT_EQ(messages->GetOutput(), "");
  vtkOutputWindow::SetInstance(nullptr);
}
