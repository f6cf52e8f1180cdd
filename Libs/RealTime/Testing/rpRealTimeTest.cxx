// Servo loop start/stop and timing statistics, histogram percentiles, SPSC ring; the load meter
// against what the test itself did (sleeps, CPU, page faults).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>
#include <time.h>

#include "rpAllocationCounter.h"
#include "rpCpuShield.h"
#include "rpServoLoop.h"
#include "rpSpscRing.h"

namespace {
class CountingTask : public rp::ServoTask {
 public:
  void ServoStarted() noexcept override { Started.store(true); }
  void Tick(const rp::TickInfo& tick) noexcept override {
    LastIndex.store(tick.Index, std::memory_order_relaxed);
    LastTime.store(tick.Time, std::memory_order_relaxed);
    LastLateness.store(tick.LatenessNs, std::memory_order_relaxed);
    Count.fetch_add(1, std::memory_order_relaxed);
    if (Allocations0 == 0) Allocations0 = rp::alloc::ThreadAllocations() + 1;
    AllocationsInTicks = rp::alloc::ThreadAllocations() + 1 - Allocations0;
  }
  void ServoStopping() noexcept override { Stopped.store(true); }
  std::atomic<bool> Started{false}, Stopped{false};
  std::atomic<uint64_t> Count{0}, LastIndex{0};
  std::atomic<double> LastTime{0};
  std::atomic<int64_t> LastLateness{0};
  uint64_t Allocations0 = 0, AllocationsInTicks = 0;  // servo thread only until joined
};
}  // namespace

TEST(TimingHistogram, PercentilesOfKnownSamples) {
  rp::TimingHistogram h(1000, 100);  // 1 µs bins
  for (int i = 1; i <= 100; ++i) h.Record(i * 1000 - 500);  // 0.5, 1.5, ..., 99.5 µs
  const rp::TimingStats s = h.Stats();
  EXPECT_EQ(s.Count, 100u);
  EXPECT_NEAR(s.P50Us, 50.0, 1e-9);
  EXPECT_NEAR(s.P99Us, 99.0, 1e-9);
  EXPECT_NEAR(s.MaxUs, 99.5, 1e-9);
  EXPECT_NEAR(s.MinUs, 0.5, 1e-9);
  EXPECT_NEAR(s.MeanUs, 50.0, 1e-9);
  h.Record(5'000'000);  // beyond the last bin: max is exact
  EXPECT_NEAR(h.Stats().MaxUs, 5000.0, 1e-9);
}

TEST(ServoLoop, StartsTicksAtRateAndStopsCleanly) {
  CountingTask task;
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.RateHz = 1000;
  std::string error;
  const auto begin = std::chrono::steady_clock::now();
  ASSERT_TRUE(loop.Start(&task, options, error)) << error;
  EXPECT_FALSE(loop.Start(&task, options, error));  // already running
  EXPECT_NE(error.find("already running"), std::string::npos);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  loop.Stop();
  // How long the loop really ran: on a loaded machine this thread may wake well after 300 ms
  // (once 336 ticks, 36 ms late), so the count is bounded by the time, not by the sleep.
  const double ranMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  loop.Stop();  // idempotent
  EXPECT_TRUE(task.Started.load());
  EXPECT_TRUE(task.Stopped.load());
  const rp::ServoStats s = loop.Stats();
  EXPECT_EQ(s.Ticks, task.Count.load());
  // An absolute 1 kHz schedule skips the periods it missed and never makes them up: at most one
  // tick per millisecond the loop ran, plus the first. At least half of them (generous: a shared
  // 2-core CI machine, sanitizers).
  EXPECT_LE(double(s.Ticks), ranMs + 1.0);
  EXPECT_GT(s.Ticks, 150u);
  // Absolute schedule: a tick runs at Index * Period plus its wake-up lateness, exactly.
  EXPECT_NEAR(task.LastTime.load(), task.LastIndex.load() * 1e-3 + task.LastLateness.load() * 1e-9, 1e-9);
  EXPECT_GT(s.Period.Count, 100u);
  EXPECT_NEAR(s.Period.MeanUs, 1000.0, 300.0);
  EXPECT_EQ(task.AllocationsInTicks, 0u);
  EXPECT_FALSE(loop.PriorityNote().empty());
  // Restartable, here with the sleep-then-spin wait.
  loop.ResetStats();
  options.SpinUs = 100;
  ASSERT_TRUE(loop.Start(&task, options, error)) << error;
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  loop.Stop();
  EXPECT_GT(loop.Stats().Ticks, 50u);
  EXPECT_NEAR(loop.Stats().Period.MeanUs, 1000.0, 300.0);
  options.SpinUs = 1000;  // a whole period: refused
  EXPECT_FALSE(loop.Start(&task, options, error));
  EXPECT_NE(error.find("spin"), std::string::npos);
}

TEST(ServoLoop, RejectsBadOptions) {
  CountingTask task;
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.RateHz = 0;
  std::string error;
  EXPECT_FALSE(loop.Start(&task, options, error));
  EXPECT_NE(error.find("rate"), std::string::npos);
  EXPECT_FALSE(loop.Start(nullptr, rp::ServoLoop::Options{}, error));
}

TEST(ServoLoop, OverrunsAreCountedAndSkippedPeriodsMissed) {
  class SlowTask : public rp::ServoTask {
   public:
    void Tick(const rp::TickInfo& tick) noexcept override {
      if (tick.Index == 5) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      if (tick.PreviousOverran) SawOverrun.store(true);
    }
    std::atomic<bool> SawOverrun{false};
  } task;
  rp::ServoLoop loop;
  std::string error;
  ASSERT_TRUE(loop.Start(&task, rp::ServoLoop::Options{}, error));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  loop.Stop();
  EXPECT_GE(loop.Stats().Overruns, 1u);
  EXPECT_GE(loop.Stats().MissedDeadlines, 3u);  // ~4 periods skipped
  EXPECT_TRUE(task.SawOverrun.load());
}

TEST(SpscRing, OrderAndDropWhenFull) {
  rp::SpscRing<int, 4> ring;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.TryPush(i));
  EXPECT_FALSE(ring.TryPush(99));
  EXPECT_EQ(ring.DroppedCount(), 1u);
  int v;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.TryPop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(ring.TryPop(v));
}

TEST(SpscRing, TwoThreadsDeliverEverythingInOrder) {
  static rp::SpscRing<uint64_t, 256> ring;
  constexpr uint64_t n = 100000;
  std::thread producer([] {
    for (uint64_t i = 0; i < n;) {
      if (ring.TryPush(i)) ++i;
    }
  });
  uint64_t expected = 0, v;
  while (expected < n) {
    if (ring.TryPop(v)) {
      ASSERT_EQ(v, expected);
      ++expected;
    }
  }
  producer.join();
}

TEST(LoadMeter, CountsTheThreadsOwnSleepsCpuAndFaults) {
  rp::LoadMeter meter;
  meter.Begin();
  // 20 sleeps: at least 20 voluntary context switches.
  for (int i = 0; i < 20; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  // 0.1 s of this thread's CPU.
  const auto spinStart = std::chrono::steady_clock::now();
  timespec cpu0, cpu1;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu0);
  volatile double sink = 0;
  do {
    for (int i = 0; i < 10000; ++i) sink = sink + i;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu1);
  } while ((cpu1.tv_sec - cpu0.tv_sec) + 1e-9 * (cpu1.tv_nsec - cpu0.tv_nsec) < 0.1 &&
           std::chrono::steady_clock::now() - spinStart < std::chrono::seconds(5));
  // 256 fresh pages touched: at least 256 minor faults.
  const size_t pages = 256, page = 4096;
  char* memory = static_cast<char*>(mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(memory, MAP_FAILED);
  for (size_t p = 0; p < pages; ++p) memory[p * page] = 1;
  munmap(memory, pages * page);
  meter.End();
  const rp::MachineLoad& l = meter.Result();
  ASSERT_TRUE(l.HasThread);
  EXPECT_GE(l.VoluntarySwitches, 20u);
  EXPECT_GE(l.ThreadCpuSeconds, 0.1 - 0.011);  // getrusage's resolution
  EXPECT_GE(l.MinorFaults, pages);
  EXPECT_EQ(l.MajorFaults, 0u);
  if (l.HasSteal) {
    EXPECT_GT(l.Cpus, 0);
    EXPECT_GE(l.MachineCpuSeconds, 0.0);
    EXPECT_LE(l.StealSeconds, l.MachineCpuSeconds + 1e-9);
  }
}

TEST(ServoLoop, ReportsWhatTheMachineDidOverTheRun) {
  CountingTask task;
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.RequestRealTimePriority = false;
  std::string error;
  ASSERT_TRUE(loop.Start(&task, options, error)) << error;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  loop.Stop();
  const rp::MachineLoad& l = loop.Load();
  ASSERT_TRUE(l.HasThread);
  // It sleeps to every deadline: about one voluntary switch per tick.
  EXPECT_GE(l.VoluntarySwitches, task.Count.load() / 2);
  EXPECT_GT(l.Seconds, 0.1);
  EXPECT_FALSE(l.MemoryLockNote.empty());
  EXPECT_EQ(l.Cpu, -1);
  EXPECT_EQ(task.AllocationsInTicks, 0u);
}

// The shield moves another process's thread off the CPU and gives it its set back; the process's
// own threads are not its business; a CPU this process may not use is refused.
TEST(CpuShield, MovesAnotherProcessOffTheCpuAndGivesItsSetBack) {
  cpu_set_t mine;
  ASSERT_EQ(sched_getaffinity(0, sizeof mine, &mine), 0);
  if (CPU_COUNT(&mine) < 2) GTEST_SKIP() << "one CPU: nowhere to move a process";
  int shielded = -1;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &mine)) shielded = c;  // the last of ours
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // a process that only waits to be killed
    for (;;) pause();
  }
  cpu_set_t set;
  auto readChild = [&] { EXPECT_EQ(sched_getaffinity(child, sizeof set, &set), 0); };
  readChild();
  ASSERT_TRUE(CPU_ISSET(shielded, &set));
  {
    rp::CpuShield shield;
    rp::CpuShield::Result result;
    std::string note;
    ASSERT_TRUE(shield.Raise(shielded, result, note)) << note;
    EXPECT_GE(result.Moved, 1) << note;
    readChild();
    EXPECT_FALSE(CPU_ISSET(shielded, &set)) << note;
    EXPECT_EQ(CPU_COUNT(&set), CPU_COUNT(&mine) - 1);
    cpu_set_t own;
    ASSERT_EQ(sched_getaffinity(0, sizeof own, &own), 0);
    EXPECT_TRUE(CPU_ISSET(shielded, &own));  // this process keeps the CPU
    shield.Lower();
    readChild();
    EXPECT_TRUE(CPU_EQUAL(&set, &mine));
  }
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  rp::CpuShield shield;
  rp::CpuShield::Result result;
  std::string note;
  EXPECT_FALSE(shield.Raise(CPU_SETSIZE + 5, result, note));
  EXPECT_NE(note.find("not available"), std::string::npos) << note;
  // The servo loop asks for the CPU it is pinned to.
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.ShieldCpu = true;
  struct Idle : rp::ServoTask {
    void Tick(const rp::TickInfo&) noexcept override {}
  } idle;
  std::string error;
  EXPECT_FALSE(loop.Start(&idle, options, error));
  EXPECT_NE(error.find("pinned to"), std::string::npos) << error;
}
