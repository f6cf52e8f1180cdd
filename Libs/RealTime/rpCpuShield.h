#pragma once
// Keeps the other processes' threads off one CPU while a real-time loop runs on it, as
// `cset shield` and `tuna --isolate` do: every thread that may also run elsewhere gets its CPU set
// without that CPU, and Lower() gives each thread the set it had. Per-CPU kernel threads stay (the
// kernel refuses to move them), threads started later are not covered, and other users' threads
// need CAP_SYS_NICE (those refused are counted as stayed, never an error). The permanent way is the
// kernel's isolcpus= or a cpuset; this is for a run. Raise and Lower allocate: call them around the
// loop, never inside it.
#include <sched.h>
#include <sys/types.h>

#include <string>
#include <vector>

namespace rp {

class CpuShield {
 public:
  struct Result {
    int Moved = 0;   // threads of other processes moved off the CPU
    int Stayed = 0;  // threads on it that could not be moved (per-CPU kernel threads, not permitted)
  };

  CpuShield() = default;
  ~CpuShield() { this->Lower(); }
  CpuShield(const CpuShield&) = delete;
  CpuShield& operator=(const CpuShield&) = delete;

  /// Moves every thread of every other process off `cpu`. False (and nothing moved) when `cpu` is
  /// not one of this process's CPUs or is the only one; `note` says what was done or why not.
  bool Raise(int cpu, Result& result, std::string& note);
  /// Gives every moved thread that still exists the CPU set it had. Safe to call twice.
  void Lower() noexcept;
  bool Raised() const { return !this->Saved.empty(); }

 private:
  struct SavedSet {
    pid_t Tid;
    cpu_set_t Set;
  };
  std::vector<SavedSet> Saved;
};

}  // namespace rp
