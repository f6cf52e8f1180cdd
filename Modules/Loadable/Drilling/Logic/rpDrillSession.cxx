#include "rpDrillSession.h"

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

// When a run is over: Finished() said so SettleSeconds ago, or the session time ran out.
struct RunEnd {
  const DrillRunOptions& Run;
  double FinishedAt = -1;
  bool operator()(const DrillState& s) {
    if (this->FinishedAt < 0 && this->Run.Finished && this->Run.Finished(s)) this->FinishedAt = s.Time;
    return (this->FinishedAt >= 0 && s.Time >= this->FinishedAt + this->Run.SettleSeconds) || s.Time >= this->Run.MaxSeconds;
  }
};
}  // namespace

DrillSession::DrillSession(HapticDevice& device, DrillVolume& bone, DrillDisplay& display)
    : Device(device), Bone(bone), Frames(display) {}

DrillSession::~DrillSession() { this->Stop(); }

bool DrillSession::Prepare(const Options& options, const TriangleMesh& protectedSurface,
                           std::unique_ptr<HapticScene> others, std::string& error) {
  if (this->Running() || this->Task) {
    error = "drilling: this session was already prepared";
    return false;
  }
  if (this->Bone.AllocatedBlocks() == 0) {
    error = "drilling: no bone to drill (build it first)";
    return false;
  }
  this->Settings = options;
  this->ProtectedTree = BVH{};
  if (!protectedSurface.Triangles.empty()) this->ProtectedTree.Build(protectedSurface);
  if (!this->Device.Open(error)) return false;
  this->DeviceOpen = true;
  this->Task = std::make_unique<DrillServo>(this->Device, this->Bone, options.Servo);
  if (!this->ProtectedTree.Empty()) this->Task->SetProtectedSurface(&this->ProtectedTree);
  if (others) this->Task->Scenes().Publish(std::move(others));
  if (options.MakeConstraints) this->Task->Constraints().Publish(options.MakeConstraints());  // the fixtures
  this->SetControl(options.Control);
  this->PathPoints.clear();
  this->Kept.clear();
  this->LastPathTime = -1;
  if (!options.RecordPath.empty()) {
    const DrillRecordingInfo info{this->Bone.Spacing(), options.Servo.FeedRate, options.Servo.ReferenceRpm, options.StartCut};
    if (!this->Writer.Open(options.RecordPath, info, error)) return false;
  }
  this->Task->EnableRecords(!options.RecordPath.empty() || options.KeepRecords || options.KeepPath);
  return true;
}

void DrillSession::SetControl(const DrillControl& control) {
  this->Rpm = control.Rpm;
  if (this->Task) this->Task->SetControl(control);
}

bool DrillSession::Start(std::string& error) {
  if (!this->Task) {
    error = "drilling: prepare the session first";
    return false;
  }
  this->Frames.SetMeshEveryFrame(true);  // the owner swaps each frame's mesh in
  if (!this->Frames.Start(this->Settings.DisplayHz, error)) return false;
  if (!this->Loop.Start(this->Task.get(), this->Settings.Loop, error)) {
    this->Frames.Stop();
    return false;
  }
  return true;
}

vtkSmartPointer<vtkPolyData> DrillSession::Update() {
  if (!this->Task) return nullptr;
  this->Task->Scenes().Collect();
  this->Task->Constraints().Collect();
  DrillRecord r;
  while (this->Task->Records().TryPop(r)) {
    this->Writer.Add(r, this->Rpm);
    if (this->Settings.KeepRecords) this->Kept.push_back({r, this->Rpm});
    if (this->Settings.KeepPath && r.Time >= this->LastPathTime + 0.01) {
      this->PathPoints.push_back(r.Proxy);
      this->LastPathTime = r.Time;
    }
  }
  return this->Frames.TakeMesh();
}

vtkSmartPointer<vtkPolyData> DrillSession::Stop() {
  this->Loop.Stop();
  this->Frames.Stop();
  vtkSmartPointer<vtkPolyData> last;
  if (this->Task) {
    this->Frames.Frame();     // the blocks the last ticks dirtied
    last = this->Update();    // and the last records
    this->Task->Scenes().Clear();
    this->Task->Constraints().Clear();
  }
  this->Writer.Close();
  if (this->DeviceOpen) this->Device.Close();
  this->DeviceOpen = false;
  return last;
}

bool DrillSession::Run(const DrillRunOptions& run, DrillRunResult& result, std::string& error) {
  result = DrillRunResult{};
  if (!this->Task) {
    error = "drilling: prepare the session first";
    return false;
  }
  const auto wallStart = std::chrono::steady_clock::now();
  if (!(run.Realtime ? this->RunRealtime(run, result, error) : this->RunScripted(run, result))) return false;
  this->Task->ReadState(result.Final);
  result.Frames = this->Frames.Frames();
  result.WallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  result.Records = std::move(this->Kept);
  this->Kept.clear();
  return true;
}

// The ticks on this thread on a simulated clock; the display's frame and Update() every
// display period of ticks.
bool DrillSession::RunScripted(const DrillRunOptions& run, DrillRunResult& result) {
  DrillServo& servo = *this->Task;
  auto step = [&](double time) {
    if (vtkSmartPointer<vtkPolyData> mesh = this->Update(); mesh && run.OnMesh) run.OnMesh(mesh);
    if (run.Progress && run.MaxSeconds > 0) run.Progress(std::min(1.0, time / run.MaxSeconds), "drilling");
  };
  RunEnd done{run};
  TimingHistogram compute(100, 20000);  // 0.1 µs bins to 2 ms
  const double period = 1.0 / (this->Settings.Loop.RateHz > 0 ? this->Settings.Loop.RateHz : 1000.0);
  const double displayPeriod = 1.0 / (this->Settings.DisplayHz > 0 ? this->Settings.DisplayHz : 30.0);
  const int perFrame = std::max(1, static_cast<int>(std::lround(displayPeriod / period)));
  TickInfo tick;
  tick.Period = period;
  this->Frames.SetMeshEveryFrame(run.MeshEveryFrame);
  servo.ServoStarted();
  DrillState state;
  LoadMeter meter;
  meter.Begin();
  for (;;) {
    tick.Time = tick.Index * period;
    if (run.Schedule) this->SetControl(run.Schedule(tick.Time));
    const int64_t t0 = ThreadCpuNs();
    servo.Tick(tick);
    const int64_t spent = ThreadCpuNs() - t0;
    compute.Record(spent);
    tick.PreviousComputeNs = spent;
    ++tick.Index;
    servo.ReadState(state);
    if (tick.Index % perFrame == 0) {
      this->Frames.Frame();
      step(tick.Time);
    }
    if (done(state)) break;
  }
  meter.End();
  result.Load = meter.Result();
  result.Load.MemoryLockNote = "scripted run: not locked";
  servo.ServoStopping();
  this->Frames.Frame();
  if (!run.MeshEveryFrame) this->Frames.PostMesh();
  step(tick.Time);
  result.Finished = done.FinishedAt >= 0;
  result.Ticks = tick.Index;
  result.TickCompute = compute.Stats();
  this->Stop();
  return true;
}

// Start(), Update() at display rate until done, Stop(): what the viewer does, on the wall clock.
bool DrillSession::RunRealtime(const DrillRunOptions& run, DrillRunResult& result, std::string& error) {
  const auto wallStart = std::chrono::steady_clock::now();
  const double displayPeriod = 1.0 / (this->Settings.DisplayHz > 0 ? this->Settings.DisplayHz : 30.0);
  auto step = [&](double time, vtkSmartPointer<vtkPolyData> mesh) {
    if (mesh && run.OnMesh) run.OnMesh(mesh);
    if (run.Progress && run.MaxSeconds > 0) run.Progress(std::min(1.0, time / run.MaxSeconds), "drilling");
  };
  RunEnd done{run};
  if (run.Schedule) this->SetControl(run.Schedule(0.0));
  if (!this->Start(error)) return false;
  DrillState state;
  for (;;) {
    std::this_thread::sleep_for(std::chrono::duration<double>(displayPeriod));
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    if (run.Schedule) this->SetControl(run.Schedule(t));
    if (this->Task->ReadState(state) && done(state)) break;
    step(t, this->Update());
    if (t > run.MaxSeconds + 5) break;  // the servo loop stalled
  }
  vtkSmartPointer<vtkPolyData> last = this->Stop();
  step(state.Time, last);
  result.Finished = done.FinishedAt >= 0;
  result.Servo = this->Loop.Stats();
  result.Load = this->Loop.Load();
  result.Ticks = result.Servo.Ticks;
  result.TickCompute = result.Servo.Compute;
  return true;
}

}  // namespace rp
