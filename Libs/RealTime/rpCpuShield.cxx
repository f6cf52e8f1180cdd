#include "rpCpuShield.h"

#include <unistd.h>

#include "rpProcEntries.h"

namespace rp {

bool CpuShield::Raise(int cpu, Result& result, std::string& note) {
  result = Result{};
  cpu_set_t mine;
  if (sched_getaffinity(0, sizeof mine, &mine) != 0 || cpu < 0 || cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, &mine)) {
    note = "CPU " + std::to_string(cpu) + " is not available to this process: not shielded";
    return false;
  }
  if (CPU_COUNT(&mine) < 2) {
    note = "one CPU only: nowhere to move the other processes";
    return false;
  }
  const pid_t self = getpid();
  ForEachProcEntry("/proc", [&](pid_t pid) {
    if (pid == self) return;  // this process's own threads: rp::PinAndIsolate's job
    ForEachProcEntry(("/proc/" + std::to_string(pid) + "/task").c_str(), [&](pid_t tid) {
      cpu_set_t set;
      if (sched_getaffinity(tid, sizeof set, &set) != 0 || !CPU_ISSET(cpu, &set)) return;
      cpu_set_t elsewhere = set;
      CPU_CLR(cpu, &elsewhere);
      if (CPU_COUNT(&elsewhere) > 0 && sched_setaffinity(tid, sizeof elsewhere, &elsewhere) == 0) {
        this->Saved.push_back({tid, set});
        ++result.Moved;
      } else {
        ++result.Stayed;
      }
    });
  });
  note = "CPU " + std::to_string(cpu) + " shielded: " + std::to_string(result.Moved) + " thread(s) of other processes moved off, " +
         std::to_string(result.Stayed) + " stayed (per-CPU kernel threads, or not permitted)";
  return true;
}

void CpuShield::Lower() noexcept {
  for (const SavedSet& s : this->Saved) sched_setaffinity(s.Tid, sizeof s.Set, &s.Set);  // a thread gone: ESRCH, fine
  this->Saved.clear();
}

}  // namespace rp
