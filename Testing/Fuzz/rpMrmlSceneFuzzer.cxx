// libFuzzer target: 3D Slicer's .mrml scene reader (rpMrmlSceneReader: the XML, node tags and
// attributes, both link forms, URL-encoded file names, transform cycles) on arbitrary bytes. A
// scene that cannot be read must add nothing (the documented all-or-nothing of a fatal error).
// Data files named by the input are looked up beside it (none exist; models and other storages
// report them skipped).
#include <cstdint>
#include <cstdlib>

#include <vtkNew.h>

#include "rpFuzzScratch.h"
#include "rpMrmlScene.h"
#include "vtkRPScene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = rpfuzz::WriteInput("fuzz.mrml", data, size);
  vtkNew<vtkRPScene> scene;
  const int before = scene->GetNumberOfNodes();
  rp::SceneTransferReport report;
  if (!rp::ReadMrmlScene(path, scene, report) && scene->GetNumberOfNodes() != before) std::abort();
  return 0;
}
