#include "rpDicomJpegLsDecoder.h"

#include <algorithm>
#include <cstdint>

#include <charls/charls.h>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcpixel.h>
#include <dcmtk/dcmdata/dcpixseq.h>
#include <dcmtk/dcmdata/dcpxitem.h>
#include <dcmtk/dcmdata/dctk.h>

namespace rp {
namespace {

constexpr charls_jpegls_errc Success{};  // 0: success, in C and C++ (enum class there)

// The compressed frames: a fragment that starts with the JPEG SOI marker (FF D8) starts a frame;
// the fragments after it, up to the next such one, continue it. Item 0 is the offset table.
bool SplitFrames(DcmPixelSequence* sequence, std::vector<std::vector<unsigned char>>& frames, std::string& error) {
  for (unsigned long i = 1; i < sequence->card(); ++i) {
    DcmPixelItem* item = nullptr;
    Uint8* data = nullptr;
    if (sequence->getItem(item, i).bad() || !item || item->getUint8Array(data).bad()) {
      error = "unreadable JPEG-LS fragment " + std::to_string(i);
      return false;
    }
    const Uint32 length = item->getLength();
    if (length == 0 || !data) continue;
    const bool startsFrame = length >= 2 && data[0] == 0xFF && data[1] == 0xD8;
    if (startsFrame || frames.empty()) frames.emplace_back();
    frames.back().insert(frames.back().end(), data, data + length);
  }
  return true;
}

}  // namespace

bool DecodeJpegLsPixels(DcmDataset* dataset, int frames, size_t frameBytes, std::vector<char>& pixels,
                        std::string& error) {
  DcmElement* element = nullptr;
  DcmPixelData* pixelData = nullptr;
  if (dataset->findAndGetElement(DCM_PixelData, element).bad() || !(pixelData = dynamic_cast<DcmPixelData*>(element))) {
    error = "no pixel data";
    return false;
  }
  DcmPixelSequence* sequence = nullptr;
  const E_TransferSyntax xfer = dataset->getOriginalXfer();
  if (pixelData->getEncapsulatedRepresentation(xfer, nullptr, sequence).bad() || !sequence) {
    error = "JPEG-LS pixel data is not encapsulated";
    return false;
  }
  std::vector<std::vector<unsigned char>> streams;
  if (!SplitFrames(sequence, streams, error)) return false;
  if (static_cast<int>(streams.size()) != frames) {
    error = "JPEG-LS pixel data holds " + std::to_string(streams.size()) + " frame(s), the header says " +
            std::to_string(frames);
    return false;
  }
  pixels.assign(frameBytes * streams.size(), 0);
  std::vector<char> frame;
  charls_jpegls_decoder* decoder = charls_jpegls_decoder_create();
  if (!decoder) {
    error = "CharLS: out of memory";
    return false;
  }
  bool ok = true;
  for (size_t f = 0; f < streams.size() && ok; ++f) {
    size_t size = 0;
    charls_jpegls_errc status = charls_jpegls_decoder_set_source_buffer(decoder, streams[f].data(), streams[f].size());
    if (status == Success) status = charls_jpegls_decoder_read_header(decoder);
    if (status == Success) status = charls_jpegls_decoder_get_destination_size(decoder, 0, &size);
    if (status == Success) {
      frame.resize(size);
      status = charls_jpegls_decoder_decode_to_buffer(decoder, frame.data(), size, 0);
    }
    if (status == Success) {
      char* out = pixels.data() + f * frameBytes;
      if (size == frameBytes) {
        std::copy(frame.begin(), frame.end(), out);
      } else if (2 * size == frameBytes) {  // an 8-bit codestream in 16-bit pixels
        for (size_t i = 0; i < size; ++i) reinterpret_cast<uint16_t*>(out)[i] = static_cast<unsigned char>(frame[i]);
      } else {
        error = "JPEG-LS frame " + std::to_string(f + 1) + " decodes to " + std::to_string(size) + " bytes, the header says " +
                std::to_string(frameBytes);
        ok = false;
        break;
      }
    }
    if (status != Success) {
      error = "CharLS cannot decode JPEG-LS frame " + std::to_string(f + 1) + " (" + charls_get_error_message(status) +
              ")";
      ok = false;
    }
  }
  charls_jpegls_decoder_destroy(decoder);
  return ok;
}

}  // namespace rp
