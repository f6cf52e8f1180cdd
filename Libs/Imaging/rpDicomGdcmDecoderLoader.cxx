#include "rpDicomGdcmDecoder.h"

#include "rpSiblingLibrary.h"

namespace rp {

bool DecodePixelsWithGdcm(const std::string& path, std::vector<char>& pixels, std::string& error) {
  // GDCM lives in its own library (rpDicomGdcmDecoder.cxx), loaded on the first JPEG 2000 series.
  using Decode = bool (*)(const std::string*, std::vector<char>*, std::string*);
  std::string loadError;
  const auto decode = SiblingLibraryFunction<Decode>(reinterpret_cast<const void*>(&DecodePixelsWithGdcm),
                                                     "libRoboPlanGdcmDecoder.so", "roboplan_gdcm_decode_pixels", loadError);
  if (!decode) {
    error = "the JPEG 2000 decoder is not available: " + loadError;
    return false;
  }
  return decode(&path, &pixels, &error);
}

}  // namespace rp
