#pragma once
// Counts heap allocations (global operator new / malloc-backed new) per thread, to prove in tests
// that a real-time hot path does not allocate. Link the RoboPlanAllocationCounter object library
// into the test executable: it replaces the global operator new/delete.
#include <cstdint>

namespace rp::alloc {
/// operator new calls made by the calling thread so far.
uint64_t ThreadAllocations() noexcept;
/// operator new calls made by all threads so far.
uint64_t TotalAllocations() noexcept;
}  // namespace rp::alloc
