#include "rpServoLoop.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace rp {

namespace {
int64_t NowNs() noexcept {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}
void SleepUntilNs(int64_t deadline) noexcept {
  timespec ts;
  ts.tv_sec = deadline / 1000000000LL;
  ts.tv_nsec = deadline % 1000000000LL;
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}
// Sleeps until `deadline - spin`, then busy-waits to the deadline.
void WaitUntilNs(int64_t deadline, int64_t spin) noexcept {
  if (spin <= 0) {
    SleepUntilNs(deadline);
    return;
  }
  SleepUntilNs(deadline - spin);
  while (NowNs() < deadline) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
}
std::atomic<bool> priorityNoteShown{false};
}  // namespace

ServoLoop::ServoLoop() = default;

ServoLoop::~ServoLoop() { this->Stop(); }

bool ServoLoop::Start(ServoTask* task, const Options& options, std::string& error) {
  if (this->Thread.joinable()) {
    error = "servo loop: already running";
    return false;
  }
  if (task == nullptr) {
    error = "servo loop: no task";
    return false;
  }
  if (!(options.SpinUs >= 0 && options.SpinUs < 1e6 / options.RateHz)) {
    error = "servo loop: spin " + std::to_string(options.SpinUs) + " us must be >= 0 and shorter than the period";
    return false;
  }
  if (!(options.RateHz >= 1.0 && options.RateHz <= 100000.0)) {
    error = "servo loop: rate " + std::to_string(options.RateHz) + " Hz is outside [1, 100000]";
    return false;
  }
  if (options.ShieldCpu && options.CpuAffinity < 0) {
    error = "servo loop: shielding a CPU needs the CPU the loop is pinned to";
    return false;
  }
  if (options.ShieldCpu) {
    std::string note;
    if (!this->Shield.Raise(options.CpuAffinity, this->ShieldResult, note)) std::fprintf(stderr, "[servo] %s\n", note.c_str());
  }
  this->StopRequested.store(false);
  this->StartState.store(0);
  this->GotRealTime.store(false);
  this->Thread = std::thread(&ServoLoop::Run, this, task, options);
  // Wait until the thread knows its scheduling class, so the note is accurate.
  while (this->StartState.load(std::memory_order_acquire) == 0) std::this_thread::yield();
  if (options.RequestRealTimePriority && !this->GotRealTime.load()) {
    this->Note = "real-time priority (SCHED_FIFO " + std::to_string(options.Priority) +
                 ") not permitted here; the servo loop runs at normal priority";
    if (!priorityNoteShown.exchange(true)) std::fprintf(stderr, "[servo] %s\n", this->Note.c_str());
  } else {
    this->Note = options.RequestRealTimePriority ? "SCHED_FIFO" : "normal priority (not requested)";
  }
  return true;
}

void ServoLoop::Stop() {
  if (!this->Thread.joinable()) return;
  this->StopRequested.store(true, std::memory_order_release);
  this->Thread.join();
  this->LoadFigures.Shielded = this->Shield.Raised();
  this->LoadFigures.ShieldMoved = this->ShieldResult.Moved;
  this->LoadFigures.ShieldStayed = this->ShieldResult.Stayed;
  this->Shield.Lower();
  this->ShieldResult = {};
  if (this->Isolated) RestoreOtherThreads();
  if (this->Locked) UnlockProcessMemory();
  this->Isolated = this->Locked = false;
}

void ServoLoop::Run(ServoTask* task, Options options) noexcept {
  if (options.RequestRealTimePriority) {
    sched_param param{};
    param.sched_priority = options.Priority;
    this->GotRealTime.store(pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0);
  }
  this->PrepareThread(options);
  this->StartState.store(1, std::memory_order_release);

  const int64_t period = static_cast<int64_t>(std::llround(1e9 / options.RateHz));
  const int64_t missThreshold = static_cast<int64_t>(options.MissThresholdS * 1e9);
  const int64_t spin = static_cast<int64_t>(options.SpinUs * 1e3);
  task->ServoStarted();
  LoadMeter meter;
  meter.Begin(this->LoadFigures.Cpu);
  const int64_t origin = NowNs() + period;
  int64_t deadline = origin;
  int64_t lastStart = 0;
  TickInfo info;
  info.Period = static_cast<double>(period) * 1e-9;
  while (!this->StopRequested.load(std::memory_order_acquire)) {
    WaitUntilNs(deadline, spin);
    if (const int64_t stall = this->StallNs.exchange(0, std::memory_order_relaxed); stall > 0)
      SleepUntilNs(NowNs() + stall);  // injected fault: the thread is not run for a while
    const int64_t start = NowNs();
    info.LatenessNs = start - deadline;
    info.Time = static_cast<double>(start - origin) * 1e-9;
    if (lastStart != 0) this->PeriodHist.Record(start - lastStart);
    this->LatenessHist.Record(info.LatenessNs);
    if (info.LatenessNs > missThreshold) this->Missed.fetch_add(1, std::memory_order_relaxed);
    lastStart = start;

    task->Tick(info);

    const int64_t end = NowNs();
    const int64_t compute = end - start;
    this->ComputeHist.Record(compute);
    info.PreviousComputeNs = compute;
    info.PreviousOverran = compute > period;
    if (info.PreviousOverran) this->Overruns.fetch_add(1, std::memory_order_relaxed);
    ++info.Index;
    this->Ticks.fetch_add(1, std::memory_order_relaxed);
    deadline += period;
    // Fell more than a period behind: skip the lost periods (counted as missed) instead of
    // firing a burst of late ticks.
    while (deadline + period < end) {
      deadline += period;
      ++info.Index;
      this->Missed.fetch_add(1, std::memory_order_relaxed);
    }
  }
  meter.End();
  task->ServoStopping();
  const MachineLoad where = this->LoadFigures;
  this->LoadFigures = meter.Result();
  this->LoadFigures.Cpu = where.Cpu;
  this->LoadFigures.OthersMovedOff = where.OthersMovedOff;
  this->LoadFigures.ThreadsMoved = where.ThreadsMoved;
  this->LoadFigures.MemoryLocked = where.MemoryLocked;
  this->LoadFigures.MemoryLockNote = where.MemoryLockNote;
}

void ServoLoop::PrepareThread(const Options& options) noexcept {
  MachineLoad& where = this->LoadFigures;
  where = MachineLoad{};
  if (options.LockMemory) {
    this->Locked = LockProcessMemory(where.MemoryLockNote);
    where.MemoryLocked = this->Locked;
  } else {
    where.MemoryLockNote = "not requested";
  }
  if (options.CpuAffinity < 0) return;
  std::string note;
  if (options.MoveOthersOff) {
    const int moved = PinAndIsolate(options.CpuAffinity, note);
    where.Cpu = moved >= 0 ? options.CpuAffinity : -1;
    where.OthersMovedOff = moved > 0;
    where.ThreadsMoved = std::max(0, moved);
    this->Isolated = moved > 0;
  } else {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(options.CpuAffinity, &set);
    if (pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0) where.Cpu = options.CpuAffinity;
  }
}

ServoStats ServoLoop::Stats() const {
  ServoStats s;
  s.Period = this->PeriodHist.Stats();
  s.Compute = this->ComputeHist.Stats();
  s.Lateness = this->LatenessHist.Stats();
  s.Ticks = this->Ticks.load(std::memory_order_relaxed);
  s.MissedDeadlines = this->Missed.load(std::memory_order_relaxed);
  s.Overruns = this->Overruns.load(std::memory_order_relaxed);
  s.RealTimePriority = this->GotRealTime.load(std::memory_order_relaxed);
  return s;
}

void ServoLoop::ResetStats() {
  if (this->Thread.joinable()) return;
  this->PeriodHist.Reset();
  this->ComputeHist.Reset();
  this->LatenessHist.Reset();
  this->Ticks.store(0);
  this->Missed.store(0);
  this->Overruns.store(0);
}

}  // namespace rp
