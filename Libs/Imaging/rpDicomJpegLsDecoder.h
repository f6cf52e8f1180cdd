#pragma once
// Internal to RoboPlanDicom: JPEG-LS pixel data decoded by CharLS 2 through its C API
// (charls_jpegls_decoder_*).
//
// Why not DCMTK's or GDCM's JPEG-LS codec: DCMTK 3.6.7's bundled CharLS 1 fork
// (libdcmtkcharls) and Debian's CharLS 2 (libcharls.so.2, which GDCM uses) both export the
// legacy JpegLsDecode / JpegLsReadHeader / JpegLsEncode under the same unversioned names. A
// process that loads both (any target linking ${ITK_LIBRARIES}, which lists ITK's DCMTK module,
// when the linker keeps every listed library, as it does under the sanitizers) serves both
// callers with whichever library was loaded first, with the other's structures: heap corruption
// and crashes in our tests. The charls_jpegls_decoder_* names exist only in CharLS 2, so this
// decoder is right whatever else the process has loaded.
#include <string>
#include <vector>

class DcmDataset;

namespace rp {

/// Decodes the encapsulated JPEG-LS pixel data of `dataset` (`frames` frames of `frameBytes`
/// bytes once decoded, one or more fragments each) into `pixels`: stored values, frames one
/// after another, this machine's byte order. False with `error` naming the problem.
bool DecodeJpegLsPixels(DcmDataset* dataset, int frames, size_t frameBytes, std::vector<char>& pixels,
                        std::string& error);

}  // namespace rp
