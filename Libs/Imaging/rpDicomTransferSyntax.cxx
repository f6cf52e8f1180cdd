#include "rpDicomTransferSyntax.h"

namespace rp {

const std::vector<TransferSyntaxInfo>& SupportedTransferSyntaxes() {
  static const std::vector<TransferSyntaxInfo> syntaxes = {
      {"1.2.840.10008.1.2", "Implicit VR Little Endian", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.1", "Explicit VR Little Endian", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.1.99", "Deflated Explicit VR Little Endian", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.2", "Explicit VR Big Endian", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.5", "RLE Lossless", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.4.50", "JPEG Baseline (process 1)", false, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.4.51", "JPEG Extended (process 2 & 4)", false, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.4.57", "JPEG Lossless (process 14)", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.4.70", "JPEG Lossless SV1 (process 14, selection value 1)", true, PixelDecoder::DCMTK},
      {"1.2.840.10008.1.2.4.80", "JPEG-LS Lossless", true, PixelDecoder::CharLS},
      {"1.2.840.10008.1.2.4.81", "JPEG-LS Near-Lossless", false, PixelDecoder::CharLS},
      {"1.2.840.10008.1.2.4.90", "JPEG 2000 Lossless Only", true, PixelDecoder::GDCM},
      {"1.2.840.10008.1.2.4.91", "JPEG 2000 (lossless or lossy)", false, PixelDecoder::GDCM},
  };
  return syntaxes;
}

const TransferSyntaxInfo* FindTransferSyntax(const std::string& uid) {
  for (const TransferSyntaxInfo& s : SupportedTransferSyntaxes())
    if (s.UID == uid) return &s;
  return nullptr;
}

std::string TransferSyntaxLabel(const std::string& uid) {
  const TransferSyntaxInfo* s = FindTransferSyntax(uid);
  return s ? s->Name + " (" + uid + ")" : uid;
}

}  // namespace rp
