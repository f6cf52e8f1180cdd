#include "rpMachineLoad.h"

#include <alloca.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "rpProcEntries.h"

namespace rp {

namespace {
int64_t WallNs() noexcept {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

// Sums one "cpu..." line of /proc/stat: user nice system idle iowait irq softirq steal.
bool ParseCpuLine(const char* line, uint64_t& total, uint64_t& busy, uint64_t& steal) noexcept {
  const char* p = std::strchr(line, ' ');
  if (p == nullptr) return false;
  uint64_t v[8] = {};
  for (int i = 0; i < 8; ++i) {
    char* end = nullptr;
    v[i] = std::strtoull(p, &end, 10);
    if (end == p) return i >= 4;  // old kernels: fewer fields
    p = end;
  }
  total = v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7];
  busy = v[0] + v[1] + v[2] + v[5] + v[6];
  steal = v[7];
  return true;
}

std::mutex* IsolationMutex() {
  static std::mutex m;
  return &m;
}
cpu_set_t originalSet;
bool haveOriginal = false;
long isolatedTid = -1;

template <typename F>
void ForEachOtherThread(long self, F&& f) noexcept {
  ForEachProcEntry("/proc/self/task", [&](pid_t tid) {
    if (tid != self) f(tid);
  });
}
}  // namespace

LoadMeter::Sample LoadMeter::Read(int cpu) noexcept {
  Sample s;
  s.WallNs = WallNs();
  if (FILE* f = std::fopen("/proc/stat", "r")) {
    char line[512];
    char want[16];
    std::snprintf(want, sizeof want, "cpu%d ", cpu);
    while (std::fgets(line, sizeof line, f)) {
      if (std::strncmp(line, "cpu", 3) != 0) break;
      uint64_t total = 0, busy = 0, steal = 0;
      if (line[3] == ' ') {
        s.Ok = ParseCpuLine(line, total, busy, steal);
        s.Total = total, s.Busy = busy, s.Steal = steal;
      } else {
        ++s.Cpus;
        if (cpu >= 0 && std::strncmp(line, want, std::strlen(want)) == 0 && ParseCpuLine(line, total, busy, steal))
          s.CpuSteal = steal;
      }
    }
    std::fclose(f);
  }
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &s.LoadAverage) != 1) s.LoadAverage = -1;
    std::fclose(f);
  }
  rusage u{};
  if (getrusage(RUSAGE_THREAD, &u) == 0) {
    s.ThreadOk = true;
    s.ThreadCpu = double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
    s.Nivcsw = uint64_t(u.ru_nivcsw);
    s.Nvcsw = uint64_t(u.ru_nvcsw);
    s.MinFlt = uint64_t(u.ru_minflt);
    s.MajFlt = uint64_t(u.ru_majflt);
  }
  return s;
}

void LoadMeter::Begin(int cpu) noexcept {
  this->Cpu = cpu;
  this->Start = Read(cpu);
}

void LoadMeter::End() noexcept {
  const Sample end = Read(this->Cpu);
  MachineLoad& l = this->Load;
  l.Seconds = double(end.WallNs - this->Start.WallNs) * 1e-9;
  const double tick = double(sysconf(_SC_CLK_TCK) > 0 ? sysconf(_SC_CLK_TCK) : 100);
  l.LoadAverage = this->Start.LoadAverage;
  l.HasSteal = this->Start.Ok && end.Ok;
  if (l.HasSteal) {
    l.Cpus = end.Cpus;
    l.StealSeconds = double(end.Steal - this->Start.Steal) / tick;
    l.MachineCpuSeconds = double(end.Total - this->Start.Total) / tick;
    l.StealPercent = l.MachineCpuSeconds > 0 ? 100.0 * l.StealSeconds / l.MachineCpuSeconds : 0.0;
    l.BusyPercent = l.MachineCpuSeconds > 0 ? 100.0 * double(end.Busy - this->Start.Busy) / tick / l.MachineCpuSeconds : 0.0;
    if (this->Cpu >= 0) l.StealOnCpuTicks = int64_t(end.CpuSteal - this->Start.CpuSteal);
  }
  l.HasThread = this->Start.ThreadOk && end.ThreadOk;
  if (l.HasThread) {
    l.ThreadCpuSeconds = end.ThreadCpu - this->Start.ThreadCpu;
    l.InvoluntarySwitches = end.Nivcsw - this->Start.Nivcsw;
    l.VoluntarySwitches = end.Nvcsw - this->Start.Nvcsw;
    l.MinorFaults = end.MinFlt - this->Start.MinFlt;
    l.MajorFaults = end.MajFlt - this->Start.MajFlt;
  }
}

bool LockProcessMemory(std::string& note, size_t stackBytes) noexcept {
#ifdef MCL_ONFAULT
  const int flags = MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT;
  const char* how = "mlockall(MCL_CURRENT|MCL_FUTURE|MCL_ONFAULT)";
#else
  const int flags = MCL_CURRENT | MCL_FUTURE;
  const char* how = "mlockall(MCL_CURRENT|MCL_FUTURE)";
#endif
  if (mlockall(flags) != 0) {
    note = std::string("mlockall refused: ") + std::strerror(errno) + " (needs CAP_IPC_LOCK or a larger RLIMIT_MEMLOCK)";
    return false;
  }
  // Fault in (and so lock) the stack the loop will use.
  volatile char* stack = static_cast<volatile char*>(alloca(stackBytes));
  for (size_t i = 0; i < stackBytes; i += 4096) stack[i] = 0;
  note = how;
  return true;
}

void UnlockProcessMemory() noexcept { munlockall(); }

int AvailableCpus() noexcept {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return CPU_COUNT(&set);
}

int PinAndIsolate(int cpu, std::string& note) noexcept {
  std::lock_guard<std::mutex> lock(*IsolationMutex());
  cpu_set_t before;
  if (pthread_getaffinity_np(pthread_self(), sizeof before, &before) != 0 || cpu < 0 || cpu >= CPU_SETSIZE ||
      !CPU_ISSET(cpu, &before)) {
    note = "CPU " + std::to_string(cpu) + " is not available to this process";
    return -1;
  }
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  if (const int e = pthread_setaffinity_np(pthread_self(), sizeof one, &one); e != 0) {
    note = std::string("sched_setaffinity refused: ") + std::strerror(e);
    return -1;
  }
  note = "pinned to CPU " + std::to_string(cpu);
  if (CPU_COUNT(&before) < 2) return 0;  // nowhere else to go
  originalSet = before;
  haveOriginal = true;
  cpu_set_t others = before;
  CPU_CLR(cpu, &others);
  isolatedTid = syscall(SYS_gettid);
  int moved = 0;
  ForEachOtherThread(isolatedTid, [&](pid_t tid) { moved += sched_setaffinity(tid, sizeof others, &others) == 0; });
  note += ", " + std::to_string(moved) + " other thread(s) moved off it";
  return moved;
}

void RestoreOtherThreads() noexcept {
  std::lock_guard<std::mutex> lock(*IsolationMutex());
  if (!haveOriginal) return;
  ForEachOtherThread(isolatedTid, [&](pid_t tid) { sched_setaffinity(tid, sizeof originalSet, &originalSet); });
  haveOriginal = false;
  isolatedTid = -1;
}

}  // namespace rp
