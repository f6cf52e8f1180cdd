#pragma once
// How a servo run's load figures (rp::MachineLoad: the hypervisor's steal, the servo thread's
// preemptions and page faults, memory lock, CPU pinning) are reported, in one place for every
// command and report that shows servo lateness (`roboplan haptics --json`, `roboplan drill
// --json`, the demo's drilling stage): the JSON object, a one-line summary, and a reading that
// says whether the misses look like the machine's or RoboPlan's.
#include <string>

#include <nlohmann/json.hpp>

#include "rpMachineLoad.h"

namespace rp {

nlohmann::json MachineLoadJson(const MachineLoad& load);
/// "steal 0.12 s of 20.0 CPU-s (0.6 %), machine 71 % busy; servo thread: 0.45 CPU-s, 3 preemptions,
/// 0 major / 12 minor faults; memory locked; pinned to CPU 1 (5 threads moved off)".
std::string MachineLoadSummary(const MachineLoad& load);
/// Whose the misses are: "no misses", "the machine: ..." (steal, preemption or major faults
/// during the run), "RoboPlan: ..." (ticks overran the period), or late wake-ups with none of
/// those (steal is counted in 10 ms ticks, so shorter stalls hide): "the host: ..." on a shielded
/// CPU, else "the host or the timer: ..." (or another process holding interrupts off).
std::string MachineLoadReading(const MachineLoad& load, uint64_t missedDeadlines, uint64_t overruns);

}  // namespace rp
