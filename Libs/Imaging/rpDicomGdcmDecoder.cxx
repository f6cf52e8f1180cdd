// The JPEG 2000 decoder as a library of its own (libRoboPlanGdcmDecoder.so, beside
// libRoboPlanImaging.so), loaded when a series first needs it (rpDicomGdcmDecoderLoader.cxx):
// GDCM's dictionaries take longer to set up when GDCM loads than most commands take to run.
#include <mutex>
#include <string>
#include <vector>

#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmTrace.h>

namespace {

bool Decode(const std::string& path, std::vector<char>& pixels, std::string& error) {
  static std::once_flag once;
  std::call_once(once, []() {
    // GDCM prints warnings on stderr; the reader's messages say what went wrong instead.
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetDebug(false);
    gdcm::Trace::SetError(false);
  });
  gdcm::ImageReader reader;
  reader.SetFileName(path.c_str());
  if (!reader.Read()) {
    error = "GDCM cannot read the file";
    return false;
  }
  const gdcm::Image& image = reader.GetImage();
  const unsigned long length = image.GetBufferLength();
  if (length == 0) {
    error = "GDCM found no pixel data";
    return false;
  }
  pixels.resize(length);
  if (!image.GetBuffer(pixels.data())) {
    pixels.clear();
    error = "GDCM cannot decode the pixel data (" + std::string(image.GetTransferSyntax().GetString()) +
            ": corrupt or truncated codestream?)";
    return false;
  }
  return true;
}

}  // namespace

/// rp::DecodePixelsWithGdcm's work (rpDicomGdcmDecoder.h).
extern "C" __attribute__((visibility("default"))) bool roboplan_gdcm_decode_pixels(const std::string* path,
                                                                                   std::vector<char>* pixels,
                                                                                   std::string* error) {
  return Decode(*path, *pixels, *error);
}
