// libFuzzer target: DICOM Segmentation objects (rpDicomSegmentation with DCMTK's dcmseg: binary
// and fractional frames, plane positions, segment table, the grid the frames span) on arbitrary
// bytes, read without a referenced series. Runs with ROBOPLAN_MEMORY_LIMIT_MB (run-fuzzer.sh) so
// that a grid the memory check would accept on a large machine is refused under the fuzzer's
// 2 GB limit.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <vtkNew.h>

#include "rpDicomSegmentation.h"
#include "rpFuzzScratch.h"
#include "vtkRPSegmentationNode.h"

// DCMTK 3.6.7 (Debian's) leaks the whole DcmSegmentation when its read fails ("Invalid Pixel
// Data", a bad dimension index ...): DcmSegmentation::loadDataset news the object, and on a failed
// read deletes the caller's pointer, which it set to NULL, instead of the object (its disassembly:
// the delete tests the out parameter); the caller never sees the object. Found here
// (regression-leak-8752..., -8093...): ~130 kB per malformed SEG. The suppression names that
// DCMTK function only, so a leak rooted in our code still fails the run; full stacks (not the
// fast unwinder, which stops in DCMTK's frames) let it match.
extern "C" const char* __asan_default_options() { return "fast_unwind_on_malloc=0"; }
extern "C" const char* __lsan_default_suppressions() { return "leak:DcmSegmentation::loadDataset\n"; }
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = rpfuzz::WriteInput("fuzz.dcm", data, size);
  vtkNew<vtkRPSegmentationNode> node;
  std::string error;
  std::vector<std::string> warnings;
  rp::ReadDicomSegmentation(path, node, error, "", &warnings);
  return 0;
}
