// libFuzzer target: the scene file (*.rpscene JSON) parser on arbitrary bytes, and the writer
// on what it parsed (a parsed document must format and parse back to the same nodes).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "rpSceneFile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rp::SceneFileDocument document;
  std::string error;
  if (!rp::ParseSceneFile(text, "fuzz.rpscene", document, error)) return 0;
  rp::SceneFileDocument again;
  if (!rp::ParseSceneFile(rp::FormatSceneFile(document), "again.rpscene", again, error)) std::abort();
  if (again.Nodes.size() != document.Nodes.size()) std::abort();
  return 0;
}
