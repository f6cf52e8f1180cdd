#pragma once
// The DICOM transfer syntaxes RoboPlan reads, the one list of them: name, whether the
// compression is lossless, and which library decodes the pixels. DCMTK parses every file and
// decodes the uncompressed, deflated, RLE and JPEG syntaxes; GDCM decodes JPEG 2000 (OpenJPEG)
// and JPEG-LS (CharLS 2).
//
// Why JPEG-LS goes to GDCM although DCMTK has a codec: DCMTK 3.6.7 bundles its own CharLS 1
// fork (libdcmtkcharls) that exports JpegLsDecode, JpegLsReadHeader and JpegLsEncode under
// the same unversioned names as Debian's CharLS 2 (libcharls.so.2, which GDCM links). In one
// process the first one loaded serves both callers with the other's structures and argument
// lists: DCMTK's JPEG-LS decoding then runs through CharLS 2 and corrupted the heap in our
// tests. So libdcmjpls is never loaded and one CharLS serves the process.
#include <string>
#include <vector>

namespace rp {

enum class PixelDecoder { DCMTK, GDCM };

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
