#pragma once
// The voxels of a gzip NRRD in one piece: the whole compressed data read at once and inflated by
// libdeflate straight into the image (ITK's NrrdIO inflates through zlib's gzread in chunks and
// computes zlib's slower CRC: about twice as long for a 512x512x300 labelmap).
#include <cstddef>
#include <string>

namespace rp {

/// Fills `voxels` (`bytes` long) from `path` when it is an attached NRRD (.nrrd) with gzip
/// encoding, no line or byte skip, and (for voxels of more than one byte) little-endian data on
/// this little-endian machine. Returns false for any other file, and for a stream that does not
/// inflate to exactly `bytes`: the caller then reads it the usual way (ITK), which reports errors.
bool ReadNrrdGzipVoxels(const std::string& path, void* voxels, size_t bytes, size_t componentSize);

}  // namespace rp
