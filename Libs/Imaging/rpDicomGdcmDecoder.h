#pragma once
// Internal to RoboPlanDicom: the pixel data of JPEG 2000 (which DCMTK 3.6.7 cannot decode),
// decoded by GDCM 3.0 (Debian's libgdcm, the one Debian's ITK links to; OpenJPEG 2.5 underneath).
//
// Only the pixels come from GDCM: headers, sorting and geometry stay with DCMTK, so a file
// reads the same whichever library decodes its pixels. GDCM is loaded on the first call
// (libRoboPlanGdcmDecoder.so beside libRoboPlanDicom.so), not with RoboPlanDicom.
#include <string>
#include <vector>

namespace rp {

/// Decodes every frame of `path` into `pixels`: stored values (no rescale), frames one after
/// another, BitsAllocated per sample, in this machine's byte order. False with `error` when
/// GDCM cannot read or decode the file.
bool DecodePixelsWithGdcm(const std::string& path, std::vector<char>& pixels, std::string& error);

}  // namespace rp
