// libFuzzer target: PLUS tracked-frame sequences (.igs.mha / .igs.nrrd: rpPlusSequenceFile's
// MetaImage and NRRD headers, per-frame fields, pixel blocks) on arbitrary bytes; what parses is
// written back by the streaming writer (rpPlusSequenceWriter) in both formats and must read back
// with as many frames, and must turn into a pose-by-pose recording.
#include <cstdint>
#include <cstdlib>

#include "rpFuzzScratch.h"
#include "rpPlusSequenceFile.h"
#include "rpTrackingRecording.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = rpfuzz::WriteInput("fuzz.igs.mha", data, size);
  rp::PlusSequence sequence;
  try {
    sequence = rp::ReadPlusSequence(path, true);
  } catch (const std::exception&) {
    return 0;  // refused with a message: fine
  }
  (void)sequence.ToRecording();
  if (sequence.FrameBytes() * sequence.Frames.size() > (1u << 20)) return 0;  // image data too large to write back here
  for (const char* name : {"again.igs.mha", "again.igs.nrrd"}) {
    const std::string again = rpfuzz::ScratchFolder() + "/" + name;
    rp::WritePlusSequence(sequence, again);
    if (rp::ReadPlusSequence(again).Frames.size() != sequence.Frames.size()) std::abort();
  }
  return 0;
}
