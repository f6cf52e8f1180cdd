// Gzip NRRD voxels inflated whole by libdeflate: the same voxels as ITK reads, and every file it
// does not take (raw, detached, skips, big-endian, a damaged stream) left to ITK.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <vector>

#include <libdeflate.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpNrrdGzipVoxels.h"
#include "rpTestOutput.h"
#include "rpVolumeIO.h"

namespace {

constexpr int Dims[3] = {33, 17, 9};
constexpr size_t Count = 33 * 17 * 9;

std::vector<short> Pattern() {
  std::vector<short> v(Count);
  for (size_t i = 0; i < Count; ++i) v[i] = static_cast<short>(static_cast<int>(i * 37 % 3001) - 1000);
  return v;
}

std::string Gzip(const void* data, size_t bytes) {
  libdeflate_compressor* c = libdeflate_alloc_compressor(6);
  std::string out(libdeflate_gzip_compress_bound(c, bytes), '\0');
  out.resize(libdeflate_gzip_compress(c, data, bytes, &out[0], out.size()));
  libdeflate_free_compressor(c);
  return out;
}

std::string Header(const std::string& extra) {
  return "NRRD0004\n# a comment: with a colon\ntype: short\ndimension: 3\nsizes: 33 17 9\n"
         "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nkinds: domain domain domain\n"
         "content:=key:=value pair\n" + extra + "\n";
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

bool ReadWithITKPath(const std::string& path, std::vector<short>& voxels, std::string& error) {
  vtkNew<vtkImageData> image;
  vtkNew<vtkMatrix4x4> ijkToRAS;
  rp::VolumeFileData data;
  data.Image = image;
  data.IJKToRAS = ijkToRAS;
  if (!rp::ReadVolumeFile(path, data, error)) return false;
  const auto* p = static_cast<const short*>(image->GetScalarPointer());
  voxels.assign(p, p + Count);
  return true;
}

}  // namespace

TEST(NrrdGzipVoxels, ReadsWhatITKWritesVoxelForVoxel) {
  const auto dir = rptest::TestDir("nrrd-gzip");
  const std::vector<short> expected = Pattern();
  vtkNew<vtkImageData> image;
  image->SetDimensions(Dims[0], Dims[1], Dims[2]);
  image->AllocateScalars(VTK_SHORT, 1);
  std::memcpy(image->GetScalarPointer(), expected.data(), Count * sizeof(short));
  vtkNew<vtkMatrix4x4> ijkToRAS;
  std::string error;
  const std::string gz = (dir / "itk-gzip.nrrd").string(), raw = (dir / "itk-raw.nrrd").string();
  ASSERT_TRUE(rp::WriteVolumeFile(gz, image, ijkToRAS, {{"Segment0_Name", "femur: left"}}, error, true)) << error;
  ASSERT_TRUE(rp::WriteVolumeFile(raw, image, ijkToRAS, {}, error, false)) << error;
  std::vector<short> voxels(Count, 0);
  EXPECT_TRUE(rp::ReadNrrdGzipVoxels(gz, voxels.data(), Count * sizeof(short), sizeof(short)));
  EXPECT_EQ(voxels, expected);
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(raw, voxels.data(), Count * sizeof(short), sizeof(short)));
  // Asked for more voxels than the stream holds: not taken (ITK then says what is wrong).
  std::vector<short> larger(Count + 1);
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(gz, larger.data(), larger.size() * sizeof(short), sizeof(short)));
}

TEST(NrrdGzipVoxels, GzipMembersOneAfterAnotherAreReadInTurn) {
  const auto dir = rptest::TestDir("nrrd-gzip-members");
  const std::vector<short> expected = Pattern();
  const size_t half = Count / 2 * sizeof(short);
  const std::string path = (dir / "two-members.nrrd").string();
  Write(path, Header("endian: little\nencoding: gzip\n") + Gzip(expected.data(), half) +
                  Gzip(reinterpret_cast<const char*>(expected.data()) + half, Count * sizeof(short) - half));
  std::vector<short> voxels(Count, 0);
  EXPECT_TRUE(rp::ReadNrrdGzipVoxels(path, voxels.data(), Count * sizeof(short), sizeof(short)));
  EXPECT_EQ(voxels, expected);
  std::string error;
  ASSERT_TRUE(ReadWithITKPath(path, voxels, error)) << error;
  EXPECT_EQ(voxels, expected);
}

TEST(NrrdGzipVoxels, OtherFilesAreLeftToITK) {
  const auto dir = rptest::TestDir("nrrd-gzip-others");
  const std::vector<short> expected = Pattern();
  const std::string stream = Gzip(expected.data(), Count * sizeof(short));
  std::vector<short> voxels(Count, 0);
  const size_t bytes = Count * sizeof(short);
  // Big-endian data: ITK swaps the bytes, this reader does not take it.
  std::vector<short> swapped(expected);
  for (short& v : swapped) v = static_cast<short>(((v & 0xff) << 8) | ((v >> 8) & 0xff));
  const std::string big = (dir / "big-endian.nrrd").string();
  Write(big, Header("endian: big\nencoding: gzip\n") + Gzip(swapped.data(), bytes));
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(big, voxels.data(), bytes, sizeof(short)));
  std::string error;
  ASSERT_TRUE(ReadWithITKPath(big, voxels, error)) << error;
  EXPECT_EQ(voxels, expected);
  // A byte skip, and a detached header naming its data file.
  const std::string skip = (dir / "byte-skip.nrrd").string();
  Write(skip, Header("endian: little\nencoding: gzip\nbyte skip: 2\n") + stream);
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(skip, voxels.data(), bytes, sizeof(short)));
  Write((dir / "detached.raw.gz").string(), stream);
  const std::string nhdr = (dir / "detached.nhdr").string();
  Write(nhdr, Header("endian: little\nencoding: gzip\ndata file: detached.raw.gz\n"));
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(nhdr, voxels.data(), bytes, sizeof(short)));
  // A damaged stream: not taken; the read fails naming the file.
  std::string damaged = stream;
  damaged.resize(damaged.size() / 2);
  const std::string cut = (dir / "damaged.nrrd").string();
  Write(cut, Header("endian: little\nencoding: gzip\n") + damaged);
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(cut, voxels.data(), bytes, sizeof(short)));
  EXPECT_FALSE(ReadWithITKPath(cut, voxels, error));
  EXPECT_NE(error.find("damaged.nrrd"), std::string::npos) << error;
  // Not a NRRD at all.
  const std::string text = (dir / "text.nrrd").string();
  Write(text, "hello\n\n");
  EXPECT_FALSE(rp::ReadNrrdGzipVoxels(text, voxels.data(), bytes, sizeof(short)));
}
