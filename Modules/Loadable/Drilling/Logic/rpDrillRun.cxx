#include "rpDrillRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <thread>

#include <vtkPolyData.h>

namespace rp {

namespace {
int64_t ThreadCpuNs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

// What every display-rate step does on the caller's thread.
struct Caller {
  DrillServo& Servo;
  DrillDisplay& Display;
  const DrillRunOptions& Options;
  DrillRunResult& Result;
  DrillRecordWriter Writer;
  double CurrentRpm = 0;

  void Step(double time) {
    DrillRecord r;
    while (this->Servo.Records().TryPop(r)) {
      this->Writer.Add(r, this->CurrentRpm);
      if (this->Options.KeepRecords) this->Result.Records.push_back({r, this->CurrentRpm});
    }
    if (vtkSmartPointer<vtkPolyData> mesh = this->Display.TakeMesh(); mesh && this->Options.OnMesh)
      this->Options.OnMesh(mesh);
    if (this->Options.Progress && this->Options.MaxSeconds > 0)
      this->Options.Progress(std::min(1.0, time / this->Options.MaxSeconds), "drilling");
  }
};
}  // namespace

bool RunDrill(DrillServo& servo, DrillDisplay& display, const DrillRunOptions& options, DrillRunResult& result,
              std::string& error) {
  result = DrillRunResult{};
  Caller caller{servo, display, options, result, {}, 0};
  if (!options.RecordPath.empty() && !caller.Writer.Open(options.RecordPath, options.RecordInfo, error)) return false;
  servo.EnableRecords(!options.RecordPath.empty() || options.KeepRecords);
  const auto wallStart = std::chrono::steady_clock::now();
  const double displayPeriod = 1.0 / (options.DisplayHz > 0 ? options.DisplayHz : 30.0);
  double finishedAt = -1;
  auto control = [&](double t) {
    if (!options.Schedule) return;
    const DrillControl c = options.Schedule(t);
    caller.CurrentRpm = c.Rpm;
    servo.SetControl(c);
  };
  auto done = [&](const DrillState& s) {
    if (finishedAt < 0 && options.Finished && options.Finished(s)) finishedAt = s.Time;
    return (finishedAt >= 0 && s.Time >= finishedAt + options.SettleSeconds) || s.Time >= options.MaxSeconds;
  };

  if (!options.Realtime) {
    TimingHistogram compute(100, 20000);  // 0.1 µs bins to 2 ms
    const double period = 1.0 / (options.Loop.RateHz > 0 ? options.Loop.RateHz : 1000.0);
    const int perFrame = std::max(1, static_cast<int>(std::lround(displayPeriod / period)));
    TickInfo tick;
    tick.Period = period;
    display.SetMeshEveryFrame(options.MeshEveryFrame);
    servo.ServoStarted();
    DrillState state;
    LoadMeter meter;
    meter.Begin();
    for (;;) {
      tick.Time = tick.Index * period;
      control(tick.Time);
      const int64_t t0 = ThreadCpuNs();
      servo.Tick(tick);
      const int64_t spent = ThreadCpuNs() - t0;
      compute.Record(spent);
      tick.PreviousComputeNs = spent;
      ++tick.Index;
      servo.ReadState(state);
      if (tick.Index % perFrame == 0) {
        display.Frame();
        caller.Step(tick.Time);
      }
      if (done(state)) break;
    }
    meter.End();
    result.Load = meter.Result();
    result.Load.MemoryLockNote = "scripted run: not locked";
    servo.ServoStopping();
    display.Frame();
    if (!options.MeshEveryFrame) display.PostMesh();
    caller.Step(tick.Time);
    result.Ticks = tick.Index;
    result.TickCompute = compute.Stats();
  } else {
    ServoLoop loop;
    control(0.0);
    display.SetMeshEveryFrame(true);  // the caller swaps each frame's mesh in
    if (!display.Start(options.DisplayHz, error)) return false;
    if (!loop.Start(&servo, options.Loop, error)) {
      display.Stop();
      return false;
    }
    DrillState state;
    for (;;) {
      std::this_thread::sleep_for(std::chrono::duration<double>(displayPeriod));
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
      control(t);
      if (servo.ReadState(state) && done(state)) break;
      caller.Step(t);
      if (t > options.MaxSeconds + 5) break;  // the servo loop stalled
    }
    loop.Stop();
    display.Stop();
    display.Frame();
    caller.Step(state.Time);
    result.Servo = loop.Stats();
    result.Load = loop.Load();
    result.Ticks = result.Servo.Ticks;
    result.TickCompute = result.Servo.Compute;
  }
  servo.ReadState(result.Final);
  result.Finished = finishedAt >= 0;
  result.Frames = display.Frames();
  result.WallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  caller.Writer.Close();
  return true;
}

double NearestRankPercentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, rank > 0 ? rank - 1 : 0)];
}

}  // namespace rp
