#include "rpServoLoadReport.h"

#include <cstdio>

namespace rp {

nlohmann::json MachineLoadJson(const MachineLoad& l) {
  nlohmann::json j = {{"seconds", l.Seconds},
                      {"memoryLocked", l.MemoryLocked},
                      {"memoryLockNote", l.MemoryLockNote},
                      {"pinnedCpu", l.Cpu},
                      {"otherThreadsMovedOff", l.OthersMovedOff},
                      {"threadsMoved", l.ThreadsMoved}};
  if (l.Shielded || l.ShieldStayed > 0)
    j["shield"] = {{"otherProcessesThreadsMoved", l.ShieldMoved}, {"threadsThatStayed", l.ShieldStayed}};
  if (l.HasSteal) {
    j["machine"] = {{"cpus", l.Cpus},
                    {"stealSeconds", l.StealSeconds},
                    {"cpuSeconds", l.MachineCpuSeconds},
                    {"stealPercent", l.StealPercent},
                    {"busyPercent", l.BusyPercent},
                    {"loadAverage1min", l.LoadAverage}};
    if (l.StealOnCpuTicks >= 0) j["machine"]["stealOnPinnedCpuTicks"] = l.StealOnCpuTicks;
  }
  if (l.HasThread)
    j["servoThread"] = {{"cpuSeconds", l.ThreadCpuSeconds},
                        {"involuntarySwitches", l.InvoluntarySwitches},
                        {"voluntarySwitches", l.VoluntarySwitches},
                        {"minorFaults", l.MinorFaults},
                        {"majorFaults", l.MajorFaults}};
  return j;
}

std::string MachineLoadSummary(const MachineLoad& l) {
  char text[512];
  std::string s;
  if (l.HasSteal) {
    std::snprintf(text, sizeof text, "steal %.2f s of %.1f CPU-s (%.2f %%), machine %.0f %% busy; ", l.StealSeconds,
                  l.MachineCpuSeconds, l.StealPercent, l.BusyPercent);
    s += text;
  }
  if (l.HasThread) {
    std::snprintf(text, sizeof text, "servo thread %.2f CPU-s, %llu preemptions, %llu major / %llu minor faults; ",
                  l.ThreadCpuSeconds, static_cast<unsigned long long>(l.InvoluntarySwitches),
                  static_cast<unsigned long long>(l.MajorFaults), static_cast<unsigned long long>(l.MinorFaults));
    s += text;
  }
  s += l.MemoryLocked ? "memory locked" : "memory not locked (" + l.MemoryLockNote + ")";
  if (l.Cpu >= 0)
    s += "; pinned to CPU " + std::to_string(l.Cpu) +
         (l.OthersMovedOff ? " (" + std::to_string(l.ThreadsMoved) + " other threads moved off)" : "") +
         (l.Shielded ? ", shielded (" + std::to_string(l.ShieldMoved) + " threads of other processes moved off)" : "");
  return s;
}

std::string MachineLoadReading(const MachineLoad& l, uint64_t missed, uint64_t overruns) {
  if (missed == 0 && overruns == 0) return "no misses";
  std::string machine;
  if (l.HasSteal && l.StealSeconds > 0) machine += "the hypervisor stole " + std::to_string(l.StealSeconds).substr(0, 5) + " s";
  if (l.HasThread && l.InvoluntarySwitches > 0)
    machine += (machine.empty() ? "" : ", ") + std::string("the servo thread was preempted ") +
               std::to_string(l.InvoluntarySwitches) + " times";
  if (l.HasThread && l.MajorFaults > 0)
    machine += (machine.empty() ? "" : ", ") + std::to_string(l.MajorFaults) + " major page faults";
  if (!machine.empty()) return "the machine: " + machine;
  return overruns > 0 ? "RoboPlan: ticks computed longer than the period, with no steal or preemption"
                      : l.Shielded
                            ? "the host: woken late on a shielded CPU although no tick overran and there was no steal "
                              "(counted in 10 ms ticks: shorter stalls do not show), preemption or major fault"
                            : "the host or the timer: woken late although no tick overran and there was no steal (counted "
                              "in 10 ms ticks: shorter stalls do not show), preemption or major fault; another process "
                              "holding interrupts off on the servo's CPU also does this (servo-wakeup-trace.py names it, "
                              "--cpu N --shield keeps the others off)";
}

}  // namespace rp
