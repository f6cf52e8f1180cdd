#pragma once
// Refuse an image that cannot fit BEFORE allocating it: a reader asks here with the grid size
// from the file's header and gets a message naming the size and the memory it would need
// ("100000 x 100000 x 100000 voxels of 1 byte would need 1e+06 GB; 21 GB of memory are
// available"), instead of std::bad_alloc deep inside VTK or ITK.
#include <cstdint>
#include <string>

namespace rp {

/// Bytes of memory this process could still get: MemAvailable from /proc/meminfo (Linux),
/// else the physical memory; 0 when unknown. ROBOPLAN_MEMORY_LIMIT_MB (environment), when set,
/// caps it (the fuzzers run with 1024).
uint64_t AvailableMemoryBytes();

/// "1.5 GB", "2e+06 GB", "340 MB": a byte count for messages.
std::string FormatBytes(double bytes);

/// True when an image of dims[0] x dims[1] x dims[2] voxels of `bytesPerVoxel` bytes (times
/// `copies`, for readers that hold the data twice while converting) fits in `available` bytes
/// (default: AvailableMemoryBytes()) and in the address space. Otherwise false, with `error`
/// naming `what`, the size and the memory needed.
bool CheckImageFitsInMemory(const int64_t dims[3], double bytesPerVoxel, const std::string& what,
                            std::string& error, double copies = 1.0, uint64_t available = 0);

}  // namespace rp
