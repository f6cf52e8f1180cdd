// libFuzzer target: 3D Slicer's .mrb bundle (rpMrmlBundle's zip unpacking through libarchive,
// then the scene reader) on arbitrary bytes. The bundle is unpacked under a private temporary
// folder; after every run that folder must be empty again (the unpacked files removed) and
// nothing may have been written beside it (no entry escapes: absolute paths, `..`, links).
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include <vtkNew.h>

#include "rpFuzzScratch.h"
#include "rpMrmlScene.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace {
size_t Entries(const fs::path& folder) {
  size_t n = 0;
  for (auto it = fs::directory_iterator(folder); it != fs::directory_iterator(); ++it) ++n;
  return n;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Bundles unpack under <scratch>/tmp (TemporaryFolder uses the system's temporary folder).
  const fs::path tmp = fs::path(rpfuzz::ScratchFolder()) / "tmp";
  fs::create_directories(tmp);
  setenv("TMPDIR", tmp.c_str(), 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = rpfuzz::WriteInput("fuzz.mrb", data, size);
  vtkNew<vtkRPScene> scene;
  const int before = scene->GetNumberOfNodes();
  rp::SceneTransferReport report;
  rp::MrmlReadOptions options;
  options.MaxBundleBytes = 16u << 20;  // a zip bomb is refused at this size, as at the memory check's
  if (!rp::ReadMrmlBundle(path, scene, report, options) && scene->GetNumberOfNodes() != before) std::abort();
  const fs::path scratch = rpfuzz::ScratchFolder();
  if (Entries(scratch / "tmp") != 0) std::abort();  // the unpacked bundle was not removed
  if (Entries(scratch) != 2) std::abort();          // something besides fuzz.mrb and tmp/: an entry escaped
  return 0;
}
