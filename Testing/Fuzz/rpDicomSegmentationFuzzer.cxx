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

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = rpfuzz::WriteInput("fuzz.dcm", data, size);
  vtkNew<vtkRPSegmentationNode> node;
  std::string error;
  std::vector<std::string> warnings;
  rp::ReadDicomSegmentation(path, node, error, "", &warnings);
  return 0;
}
