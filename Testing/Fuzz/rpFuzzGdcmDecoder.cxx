// The fuzzers link the parser sources statically: DecodePixelsWithGdcm calls the GDCM decoder
// (rpDicomGdcmDecoder.cxx, linked in) directly instead of loading libRoboPlanGdcmDecoder.so beside
// the library as RoboPlanImaging does (rpDicomGdcmDecoderLoader.cxx), so JPEG 2000 stays fuzzed.
#include "rpDicomGdcmDecoder.h"

extern "C" bool roboplan_gdcm_decode_pixels(const std::string* path, std::vector<char>* pixels, std::string* error);

namespace rp {

bool DecodePixelsWithGdcm(const std::string& path, std::vector<char>& pixels, std::string& error) {
  return roboplan_gdcm_decode_pixels(&path, &pixels, &error);
}

}  // namespace rp
