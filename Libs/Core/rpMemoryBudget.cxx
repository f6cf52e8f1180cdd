#include "rpMemoryBudget.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace rp {

namespace {
uint64_t MemoryFromTheSystem() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kilobytes = 0;
  std::string unit;
  while (meminfo >> key >> kilobytes >> unit) {
    if (key == "MemAvailable:") return kilobytes * 1024;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
}
}  // namespace

uint64_t AvailableMemoryBytes() {
  const uint64_t system = MemoryFromTheSystem();
  // A cap for runs that must stay small (the fuzzers, whose 2 GB limit counts any larger
  // allocation as a failure; a shared machine).
  const char* cap = std::getenv("ROBOPLAN_MEMORY_LIMIT_MB");
  const double megabytes = cap ? std::atof(cap) : 0.0;
  if (megabytes > 0 && (system == 0 || megabytes * 1048576.0 < double(system))) return uint64_t(megabytes * 1048576.0);
  return system;
}

std::string FormatBytes(double bytes) {
  const double gb = bytes / 1e9;
  char text[64];
  if (gb >= 1e4)
    std::snprintf(text, sizeof text, "%.3g GB", gb);  // "1e+06 GB"
  else if (gb >= 1.0)
    std::snprintf(text, sizeof text, "%.1f GB", gb);
  else if (bytes >= 1e6)
    std::snprintf(text, sizeof text, "%.0f MB", bytes / 1e6);
  else
    std::snprintf(text, sizeof text, "%.0f kB", bytes / 1e3);
  return text;
}

bool CheckImageFitsInMemory(const int64_t dims[3], double bytesPerVoxel, const std::string& what,
                            std::string& error, double copies, uint64_t available) {
  std::ostringstream size;
  size << dims[0] << " x " << dims[1] << " x " << dims[2] << " voxels";
  for (int i = 0; i < 3; ++i) {
    if (dims[i] <= 0) {
      error = what + ": invalid size " + size.str();
      return false;
    }
  }
  // In double: the product of three int64 overflows long before it stops being meaningful.
  const double voxels = double(dims[0]) * double(dims[1]) * double(dims[2]);
  const double needed = voxels * bytesPerVoxel * copies;
  std::ostringstream voxelSize;
  voxelSize << bytesPerVoxel << (bytesPerVoxel == 1.0 ? " byte" : " bytes");
  const std::string head = what + ": " + size.str() + " of " + voxelSize.str() + " would need " + FormatBytes(needed);
  // VTK indexes voxels with vtkIdType (int64); a size_t byte count must not overflow either.
  if (voxels > 9.0e18 || needed > double(std::numeric_limits<size_t>::max()) / 2) {
    error = head + ", more than any computer can address";
    return false;
  }
  if (available == 0) available = AvailableMemoryBytes();
  if (available > 0 && needed > double(available)) {
    error = head + "; only " + FormatBytes(double(available)) + " of memory are available";
    return false;
  }
  return true;
}

}  // namespace rp
