#pragma once
// What the machine did to a real-time loop over one run, so a missed deadline can be told apart
// as the machine's (the hypervisor stole the CPU, another thread preempted ours, the loop's
// pages were not resident) or the code's (the tick's own compute):
//  - steal: CPU time the hypervisor gave to other guests (/proc/stat, all CPUs and the servo's
//    CPU), against the machine's total CPU time in the same interval;
//  - the loop thread's own figures (getrusage RUSAGE_THREAD on that thread): CPU time,
//    involuntary context switches (preempted: by a higher-priority thread, or its time slice
//    ran out), voluntary ones (it slept: once per period is normal), minor/major page faults;
//  - whether memory was locked (mlockall) and the thread pinned to a CPU with the process's other
//    threads moved off it.
// LoadMeter samples before and after a run, on the thread it measures (Begin/End each read
// /proc/stat once and call getrusage once): never on a hot path.
#include <cstdint>
#include <string>

namespace rp {

struct MachineLoad {
  double Seconds = 0;               // wall time between Begin and End
  // The whole machine (all CPUs), from /proc/stat.
  bool HasSteal = false;            // /proc/stat was readable
  double StealSeconds = 0;          // CPU-seconds stolen by the hypervisor, all CPUs
  double MachineCpuSeconds = 0;     // CPU-seconds that passed on all CPUs (busy + idle + steal)
  double StealPercent = 0;          // StealSeconds / MachineCpuSeconds
  double BusyPercent = 0;           // the machine's CPUs busy (user+nice+system+irq+softirq), any process
  int Cpus = 0;                     // CPUs counted in /proc/stat
  double LoadAverage = -1;          // 1-minute load average at Begin (/proc/loadavg), −1 unknown
  // The measured thread (RUSAGE_THREAD).
  bool HasThread = false;
  double ThreadCpuSeconds = 0;      // user + system
  uint64_t InvoluntarySwitches = 0; // preempted
  uint64_t VoluntarySwitches = 0;   // slept
  uint64_t MinorFaults = 0, MajorFaults = 0;
  // Where it ran and how memory was held (filled by the owner, e.g. rp::ServoLoop).
  int Cpu = -1;                     // the CPU the thread was pinned to (−1: not pinned)
  bool OthersMovedOff = false;      // the process's other threads were moved off that CPU
  int ThreadsMoved = 0;
  bool Shielded = false;            // other processes' threads were kept off that CPU (rp::CpuShield)
  int ShieldMoved = 0, ShieldStayed = 0;
  bool MemoryLocked = false;        // mlockall succeeded
  std::string MemoryLockNote;       // why not, or how ("mlockall(MCL_CURRENT|MCL_FUTURE|MCL_ONFAULT)")
  int64_t StealOnCpuTicks = -1;     // steal on the pinned CPU (clock ticks), −1 unknown
};

/// Reads the machine's and the calling thread's counters at Begin() and End(); Result() is the
/// difference. Cheap (one small file read, one system call), never for the inside of a tick.
class LoadMeter {
 public:
  void Begin(int cpu = -1) noexcept;
  void End() noexcept;
  const MachineLoad& Result() const { return this->Load; }
  MachineLoad& Result() { return this->Load; }

 private:
  struct Sample {
    bool Ok = false, ThreadOk = false;
    uint64_t Steal = 0, Total = 0, Busy = 0, CpuSteal = 0;
    int Cpus = 0;
    double LoadAverage = -1;
    double ThreadCpu = 0;
    uint64_t Nivcsw = 0, Nvcsw = 0, MinFlt = 0, MajFlt = 0;
    int64_t WallNs = 0;
  };
  static Sample Read(int cpu) noexcept;
  Sample Start;
  int Cpu = -1;
  MachineLoad Load;
};

/// Locks the process's memory (mlockall; pages lock as they fault, so nothing is prefaulted but
/// nothing resident is paged out) and touches `stackBytes` of the calling thread's stack. False
/// with `note` saying why when the kernel refused (e.g. RLIMIT_MEMLOCK without CAP_IPC_LOCK).
bool LockProcessMemory(std::string& note, size_t stackBytes = 256 * 1024) noexcept;
void UnlockProcessMemory() noexcept;

/// Pins the calling thread to `cpu` and moves every other thread of the process off it (threads
/// created later inherit their creator's set). Returns how many other threads were moved, −1
/// when the kernel refused the pinning (`note` says why). RestoreOtherThreads() gives the other
/// threads all CPUs back.
int PinAndIsolate(int cpu, std::string& note) noexcept;
void RestoreOtherThreads() noexcept;
/// CPUs this process may run on.
int AvailableCpus() noexcept;

}  // namespace rp
