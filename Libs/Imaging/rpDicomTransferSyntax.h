#pragma once
// The DICOM transfer syntaxes RoboPlan reads, the one list of them: name, whether the
// compression is lossless, and which library decodes the pixels. DCMTK parses every file and
// decodes the uncompressed, deflated, RLE and JPEG syntaxes; GDCM decodes JPEG 2000 (OpenJPEG);
// CharLS 2's own C API decodes JPEG-LS (why not DCMTK's or GDCM's: rpDicomJpegLsDecoder.h).
#include <string>
#include <vector>

namespace rp {

enum class PixelDecoder { DCMTK, GDCM, CharLS };

struct TransferSyntaxInfo {
  std::string UID;
  std::string Name;
  bool Lossless = true;
  PixelDecoder Decoder = PixelDecoder::DCMTK;
};

/// Every transfer syntax the reader decodes (tested with files made by gdcmconv, dcmcjpeg,
/// dcmcjpls, dcmcrle and dcmconv from real series).
const std::vector<TransferSyntaxInfo>& SupportedTransferSyntaxes();

/// The entry for `uid`, or nullptr when the reader does not decode it.
const TransferSyntaxInfo* FindTransferSyntax(const std::string& uid);

/// "JPEG 2000 (1.2.840.10008.1.2.4.91)" for messages; the bare UID when unknown.
std::string TransferSyntaxLabel(const std::string& uid);

}  // namespace rp
