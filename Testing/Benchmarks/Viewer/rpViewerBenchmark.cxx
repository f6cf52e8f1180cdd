// Viewer frame time while touching (issue 14): the 4-up at 1400×1100 (four 700×550 views, as the
// Qt viewer draws them: one render window per view) on the demo's scene, while the simulated
// haptic device runs its 1 kHz servo loop along a stroke over the anatomy and the three slices
// follow its proxy (the scene's slice nodes follow the HapticProxy node).
//
//  * Naive (what one writes first): every servo update is pushed to the scene at once and all
//    four views are re-rendered at full detail, as fast as they go.
//  * Display rate (the viewer): a 30 Hz tick copies the latest servo state into the scene once,
//    re-slices only the slices whose plane moved, renders only the views that changed, with the
//    display level of detail while the scene moves and one full-detail frame when it stops
//    (rp::RenderScheduler, as the main window).
//
// Frame time = from the tick to the last view finished (glFinish), p50/p95 (ms), and frames per
// second, as counters in the JSON (--benchmark_out) and in viewer-frames.json/.csv with a chart
// (viewer-frame-times.png) in $ROBOPLAN_BENCHMARK_OUTPUT, with the 4-up as drawn while touching
// (viewer-4up-while-touching.png) and the still frame after the tool stops (viewer-4up-still.png).
// Target: p95 ≤ 33 ms on 2 cores with Mesa llvmpipe. Without a display it draws on a private Xvfb
// (1920x1080x24, rpXDisplay.h); the run's conditions (GL renderer, screen depth, build type, load,
// steal...) are printed and written with the figures (rpBenchmarkConditions.h).
//
// The scene: $ROBOPLAN_VIEWER_BENCH_SCENE, else the demo's scene in <output>/viewer-scene (made
// once with `roboplan demo --no-screenshots`, whatever anatomy the demo uses). A quick run
// (ROBOPLAN_BENCHMARK_QUICK) strokes for 1 s, on the small demo's scene (<output>/viewer-scene-small).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <time.h>

#include <nlohmann/json.hpp>
#include <vtkActor.h>
#include <vtkAlgorithm.h>
#include <vtkAlgorithmOutput.h>
#include <vtkCellArray.h>
#include <vtkMapper.h>
#include <vtkPropCollection.h>
#include <vtkRenderer.h>
#include <vtkNew.h>
#include <vtkImageAppend.h>
#include <vtkPNGWriter.h>
#include <vtkPolyData.h>
#include <vtkWindowToImageFilter.h>
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpXDisplay.h"
#include "rpHapticSceneBridge.h"
#include "rpHapticSession.h"
#include "rpMaterial.h"
#include "rpRenderScheduler.h"
#include "rpSceneIO.h"
#include "rpSimulatedDevice.h"
#include "rpView.h"
#include "vtkRPCachedRenderPass.h"
#include "rpViewController.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int ViewWidth = 700, ViewHeight = 550;  // the 4-up at 1400 × 1100
constexpr double StrokeSeconds = 8.0;
constexpr double DisplayPeriod = 1.0 / 30.0;

// CPU time (ms) of the calling thread, or of the whole process (llvmpipe's threads included).
double CpuMs(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

double Seconds() {
  const char* text = std::getenv("ROBOPLAN_VIEWER_BENCH_SECONDS");
  return text ? std::max(1.0, std::atof(text)) : rp::bench::QuickRun() ? 1.0 : StrokeSeconds;
}

// The demo's scene: made once, reused by later runs (a quick run's on the small phantom, apart).
std::string ScenePath(std::string& error) {
  if (const char* path = std::getenv("ROBOPLAN_VIEWER_BENCH_SCENE")) return path;
  const bool quick = rp::bench::QuickRun();
  const fs::path folder = fs::path(rp::bench::OutputDirectory()) / (quick ? "viewer-scene-small" : "viewer-scene");
  const fs::path scene = folder / "scene.rpscene";
  if (fs::exists(scene)) return scene.string();
  std::cerr << "[viewer-bench] making the demo's scene in " << folder << " (roboplan demo)...\n";
  const std::string command = std::string(ROBOPLAN_BINARY_DIR) + "/bin/roboplan demo --no-screenshots --haptic-seconds 1 " +
                              (quick ? "--size small " : "") + "--out '" + folder.string() + "' > '" +
                              (folder.string() + ".log") + "' 2>&1";
  fs::create_directories(folder);
  if (std::system(command.c_str()) != 0 && !fs::exists(scene)) {
    error = "roboplan demo failed (see " + folder.string() + ".log)";
    return {};
  }
  return scene.string();
}

// A stroke over the anatomy in the device frame (= RAS here): around the haptic models' centre
// at mid height, dipping in and out of the surfaces, ~40 mm/s, so the proxy slides on tissue and
// all three slices move every frame.
std::shared_ptr<rp::WaypointTrajectory> Stroke(const rp::HapticScene& scene, double seconds) {
  rp::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const rp::Vec3& p : scene.Mesh.Points) lo = rp::Min(lo, p), hi = rp::Max(hi, p);
  const rp::Vec3 centre = (lo + hi) * 0.5;
  const double rx = 0.45 * (hi.x - lo.x), ry = 0.45 * (hi.y - lo.y), rz = 0.2 * (hi.z - lo.z);
  std::vector<double> times;
  std::vector<rp::Vec3> points;
  const int samples = static_cast<int>(seconds * 50);
  for (int i = 0; i <= samples; ++i) {
    const double t = seconds * i / samples, a = 2 * M_PI * t / seconds;
    const double in = 0.85 + 0.25 * std::sin(5 * a);  // in and out of the surface
    times.push_back(t);
    points.push_back({centre.x + in * rx * std::cos(a), centre.y + in * ry * std::sin(a), centre.z + rz * std::sin(2 * a)});
  }
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::string error;
  if (!path->Set(times, points, error)) return nullptr;
  return path;
}

struct Percentiles {
  double P50 = 0, P95 = 0, Max = 0, Mean = 0;
};

Percentiles Summarize(std::vector<double> ms) {
  Percentiles p;
  if (ms.empty()) return p;
  std::sort(ms.begin(), ms.end());
  auto at = [&ms](double q) { return ms[std::min(ms.size() - 1, static_cast<size_t>(q * double(ms.size() - 1) + 0.5))]; };
  p.P50 = at(0.50);
  p.P95 = at(0.95);
  p.Max = ms.back();
  for (double v : ms) p.Mean += v / double(ms.size());
  return p;
}

size_t Triangles(vtkRPScene* scene, bool visibleOnly) {
  size_t n = 0;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (visibleOnly && !model->GetVisibility()) continue;
    if (model->GetPolyData()) n += static_cast<size_t>(model->GetPolyData()->GetNumberOfPolys());
  }
  return n;
}

// The scene, the viewer's four views in four offscreen windows, and a haptic session.
class Rig {
 public:
  bool Open(std::string& error) {
    const std::string path = ScenePath(error);
    if (path.empty()) return false;
    const rp::SceneLoadReport report = rp::LoadScene(this->Scene, path);
    if (!report.Ok) {
      error = report.Error;
      return false;
    }
    this->SceneFile = path;
    this->Controller = std::make_unique<rp::ViewController>(this->Scene);
    for (int kind = 0; kind < 4; ++kind) {
      vtkRenderWindow* window = this->Windows[static_cast<size_t>(kind)];
      // Debian's VTK draws through GLX: $DISPLAY or a private Xvfb, never VTK's own connection.
      if (!rp::PrepareOffscreenWindow(window, error)) return false;
      window->SetMultiSamples(0);
      window->SetSize(ViewWidth, ViewHeight);
      const double full[4] = {0, 0, 1, 1};
      this->View(kind)->AttachToRenderWindow(window, full);
    }
    this->Controller->ResetCameras3D();
    // What the viewer does once on load (shaders compiled, meshes uploaded, display meshes and
    // outline indices made): not part of a frame while touching.
    for (bool interactive : {false, true, false}) {
      for (int kind = 0; kind < 4; ++kind) {
        this->View(kind)->SetInteractive(interactive);
        this->Render(kind);
      }
    }
    this->TakeViewMeanMs();
    rp::bench::Conditions::Process().NoteRenderWindow(this->Windows[0]);
    return true;
  }

  rp::View* View(int kind) const { return this->Controller->GetView(static_cast<rp::ViewKind>(kind)); }

  bool StartHaptics(std::string& error) {
    std::vector<std::string> warnings;
    rp::HapticSession::Options options;
    if (!rp::LoadMaterialTable(options.Materials, error)) return false;
    auto preview = rp::HapticScene::Build(rp::CollectHapticMeshes(this->Scene, warnings), options.Materials, warnings, error);
    if (!preview || preview->Tree.Empty()) {
      error = "no haptic models in the scene (" + error + ")";
      return false;
    }
    this->Device = std::make_unique<rp::SimulatedDevice>();
    this->Device->SetTrajectory(Stroke(*preview, Seconds()));
    this->Session = std::make_unique<rp::HapticSession>(*this->Device);
    options.RampSeconds = 0.1;
    if (!this->Session->Start(this->Scene, options, error)) return false;
    this->Session->Update();  // the proxy node exists from here
    vtkRPNode* proxy = this->Scene->GetFirstNodeByName(rp::HapticProxyName);
    if (!proxy || !vtkRPSliceNode::SetAllSlicesFollow(this->Scene, proxy->GetID())) {
      error = "no HapticProxy node to follow";
      return false;
    }
    return true;
  }

  void StopHaptics() {
    if (this->Session) this->Session->Stop();
    vtkRPSliceNode::SetAllSlicesFollow(this->Scene, "");
    this->Session.reset();
    this->Device.reset();
  }

  // Renders a view and waits for the GPU (llvmpipe) to finish it.
  void Render(int kind) {
    this->Submit(kind);
    this->Windows[static_cast<size_t>(kind)]->WaitForCompletion();
  }
  // Issues a view's drawing without waiting for it (as the Qt viewer does: the GPU, here
  // llvmpipe's rasterizer threads, draws one view while the CPU prepares the next); the time
  // counted for the view is its CPU side. WaitForFrame() then waits for every submitted view.
  void Submit(int kind) {
    vtkRenderWindow* window = this->Windows[static_cast<size_t>(kind)];
    this->View(kind)->MarkRendered();
    const auto t0 = Clock::now();
    window->Render();
    this->ViewMs[static_cast<size_t>(kind)] += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    ++this->ViewRenders[static_cast<size_t>(kind)];
    this->Submitted[static_cast<size_t>(kind)] = true;
  }
  void WaitForFrame() {
    for (size_t kind = 0; kind < 4; ++kind) {
      if (this->Submitted[kind]) this->Windows[kind]->WaitForCompletion();
      this->Submitted[kind] = false;
    }
  }
  std::array<bool, 4> Submitted{};
  std::array<double, 4> ViewMs{};
  std::array<int, 4> ViewRenders{};

  // Mean render time of each view since the last call (ms), and starts counting again.
  std::array<double, 4> TakeViewMeanMs() {
    std::array<double, 4> mean{};
    for (size_t k = 0; k < 4; ++k) {
      mean[k] = this->ViewRenders[k] ? this->ViewMs[k] / this->ViewRenders[k] : 0.0;
      this->ViewMs[k] = 0;
      this->ViewRenders[k] = 0;
    }
    return mean;
  }

  // The four views as the Qt viewer lays them out (axial | 3D over sagittal | coronal), PNG.
  void SavePicture(const std::string& path) {
    vtkNew<vtkImageAppend> top, bottom, rows;
    top->SetAppendAxis(0);
    bottom->SetAppendAxis(0);
    rows->SetAppendAxis(1);
    std::array<vtkNew<vtkWindowToImageFilter>, 4> grabs;
    for (int kind = 0; kind < 4; ++kind) {
      grabs[static_cast<size_t>(kind)]->SetInput(this->Windows[static_cast<size_t>(kind)]);
      grabs[static_cast<size_t>(kind)]->SetInputBufferTypeToRGB();
      grabs[static_cast<size_t>(kind)]->ReadFrontBufferOff();
      grabs[static_cast<size_t>(kind)]->Update();
    }
    top->AddInputConnection(grabs[0]->GetOutputPort());     // axial
    top->AddInputConnection(grabs[3]->GetOutputPort());     // 3D
    bottom->AddInputConnection(grabs[1]->GetOutputPort());  // sagittal
    bottom->AddInputConnection(grabs[2]->GetOutputPort());  // coronal
    rows->AddInputConnection(bottom->GetOutputPort());      // VTK images grow upwards
    rows->AddInputConnection(top->GetOutputPort());
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetInputConnection(rows->GetOutputPort());
    writer->Write();
  }

  int Reslices() const {
    int n = 0;
    for (int kind = 0; kind < 3; ++kind) n += this->Controller->GetSliceLogic(static_cast<rp::ViewKind>(kind))->GetNumberOfReslices();
    return n;
  }
  int PicturesMadeAhead() const {
    int n = 0;
    for (int kind = 0; kind < 3; ++kind) n += this->Controller->GetSliceLogic(static_cast<rp::ViewKind>(kind))->GetNumberOfPicturesMadeAhead();
    return n;
  }

  vtkNew<vtkRPScene> Scene;
  std::string SceneFile;
  std::unique_ptr<rp::ViewController> Controller;
  std::array<vtkNew<vtkRenderWindow>, 4> Windows;
  std::unique_ptr<rp::SimulatedDevice> Device;
  std::unique_ptr<rp::HapticSession> Session;
};

Rig* OpenedRig = nullptr;  // once a benchmark asked for it

Rig* TheRig() {
  static Rig* rig = OpenedRig = [] {
    auto* r = new Rig;
    std::string error;
    if (!r->Open(error)) {
      std::cerr << "[viewer-bench] " << error << "\n";
      delete r;
      return static_cast<Rig*>(nullptr);
    }
    return r;
  }();
  return rig;
}

struct Run {
  std::string Name;
  std::vector<double> FrameMs, FrameAt;  // frame time and when it started (s)
  std::vector<int> ViewsRendered;
  std::vector<std::array<double, 4>> FrameViewMs;  // per frame: each view's render call (ms)
  std::vector<double> FrameSceneMs;  // per frame: servo state into the scene (ms)
  // Per frame: slice pictures made. The proxy holds still on a surface for part of the stroke; then
  // only the tool moves and no picture changes. Frames that made pictures are the hard ones.
  std::vector<int> FramePictures;
  int Reslices = 0, PicturesAhead = 0;  // slice pictures made; of those, made ahead on a worker
  int ModelLayerRenders = 0, ModelLayerCopies = 0;  // 3D frames that drew the models / copied their kept picture
  double Seconds = 0;
  std::array<double, 4> ViewMeanMs{};  // mean render time of each view (axial, sagittal, coronal, 3D)
  double SceneMs = 0;  // summed: servo state into the scene
  // Summed over the frames: CPU time of the main thread and of the whole process. Beside the
  // frame time they tell whether a frame is work (CPU busy) or waiting (for llvmpipe, X).
  double MainCpuMs = 0, ProcessCpuMs = 0, FrameSumMs = 0;
};
std::vector<Run> Runs;

// The frames of a run that made slice pictures (the slices moved).
std::vector<double> FramesWithPictures(const Run& run) {
  std::vector<double> ms;
  for (size_t i = 0; i < run.FramePictures.size() && i < run.FrameMs.size(); ++i) {
    if (run.FramePictures[i] > 0) ms.push_back(run.FrameMs[i]);
  }
  return ms;
}

void Report(benchmark::State& state, const Run& run) {
  const Percentiles p = Summarize(run.FrameMs);
  const std::vector<double> moving = FramesWithPictures(run);
  const Percentiles m = Summarize(moving);
  if (!run.FramePictures.empty()) {
    state.counters["slices_moving_frames"] = double(moving.size());
    state.counters["slices_moving_p95_ms"] = m.P95;
  }
  state.counters["p50_ms"] = p.P50;
  state.counters["p95_ms"] = p.P95;
  state.counters["max_ms"] = p.Max;
  state.counters["fps"] = double(run.FrameMs.size()) / std::max(1e-9, run.Seconds);
  state.counters["frames"] = double(run.FrameMs.size());
  double views = 0;
  for (int v : run.ViewsRendered) views += v;
  state.counters["views_per_frame"] = run.FrameMs.empty() ? 0 : views / double(run.FrameMs.size());
  state.counters["reslices"] = run.Reslices;
  state.counters["pictures_made_ahead"] = run.PicturesAhead;
  state.counters["model_layer_renders"] = run.ModelLayerRenders;
  state.counters["model_layer_copies"] = run.ModelLayerCopies;
  // CPU per frame depends much less on other load than the frame's wall time does: the figure to
  // compare changes by on a busy machine.
  const double frames = double(std::max<size_t>(1, run.FrameMs.size()));
  if (run.FrameSumMs > 0) {
    state.counters["main_cpu_ms_per_frame"] = run.MainCpuMs / frames;
    state.counters["process_cpu_ms_per_frame"] = run.ProcessCpuMs / frames;
  }
  std::cerr << "[viewer-bench] " << run.Name << ": " << run.FrameMs.size() << " frames in " << run.Seconds << " s, p50 "
            << p.P50 << " ms, p95 " << p.P95 << " ms, max " << p.Max << " ms, "
            << state.counters["fps"].value << " fps, " << state.counters["views_per_frame"].value << " views/frame, "
            << run.Reslices << " reslices (" << run.PicturesAhead << " made ahead), 3D models drawn " << run.ModelLayerRenders << " / kept picture copied "
            << run.ModelLayerCopies << "; per view (ms) axial " << run.ViewMeanMs[0] << ", sagittal "
            << run.ViewMeanMs[1] << ", coronal " << run.ViewMeanMs[2] << ", 3D " << run.ViewMeanMs[3]
            << "; per frame: scene update " << run.SceneMs / std::max<size_t>(1, run.FrameMs.size()) << " ms";
  if (!run.FramePictures.empty()) {
    std::cerr << "; frames whose slices moved: " << moving.size() << ", p50 " << m.P50 << " ms, p95 " << m.P95 << " ms";
  }
  if (run.FrameSumMs > 0) {
    // The haptic servo thread's CPU is in the process time too (about 1 ms of each 1 ms tick
    // when it spins; it sleeps here), so this is an upper bound of the rendering's CPU.
    std::cerr << "; main thread busy " << 100.0 * run.MainCpuMs / run.FrameSumMs << " % of the frame time, process CPU "
              << run.ProcessCpuMs / run.FrameSumMs << " cores; CPU per frame: main thread " << run.MainCpuMs / frames
              << " ms, process " << run.ProcessCpuMs / frames << " ms";
  }
  std::cerr << "\n";
}

// Naive: every update pushed and all four views rendered at full detail, back to back.
void BM_Viewer4Up_Naive(benchmark::State& state) {
  Rig* rig = TheRig();
  if (!rig) {
    state.SkipWithError("no scene (see the message above)");
    return;
  }
  for (auto _ : state) {
    std::string error;
    if (!rig->StartHaptics(error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    Run run;
    run.Name = "naive";
    rig->View(3)->SetModelLayerCaching(false);  // every model drawn every tick
    const int reslices = rig->Reslices();
    const auto start = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - start).count() < Seconds()) {
      const auto t0 = Clock::now();
      rig->Session->Update();
      for (int kind = 0; kind < 4; ++kind) rig->Submit(kind);
      rig->WaitForFrame();
      const auto t1 = Clock::now();
      run.FrameMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      run.FrameAt.push_back(std::chrono::duration<double>(t0 - start).count());
      run.ViewsRendered.push_back(4);
    }
    run.Seconds = std::chrono::duration<double>(Clock::now() - start).count();
    run.Reslices = rig->Reslices() - reslices;
    run.ViewMeanMs = rig->TakeViewMeanMs();
    rig->StopHaptics();
    rig->View(3)->SetModelLayerCaching(true);
    Report(state, run);
    Runs.push_back(run);
  }
}

// The viewer's way: a 30 Hz display tick; only what changed is re-sliced and rendered.
void BM_Viewer4Up_DisplayRate(benchmark::State& state) {
  Rig* rig = TheRig();
  if (!rig) {
    state.SkipWithError("no scene (see the message above)");
    return;
  }
  for (auto _ : state) {
    std::string error;
    if (!rig->StartHaptics(error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    rp::RenderScheduler scheduler;
    for (int kind = 0; kind < 4; ++kind) {
      scheduler.AddView(rig->View(kind), [rig, kind]() { rig->Submit(kind); });
    }
    Run run;
    run.Name = "display rate";
    const int reslices = rig->Reslices(), ahead = rig->PicturesMadeAhead();
    vtkRPCachedRenderPass* models = rig->View(3)->GetModelLayerPass();
    const int modelRenders = models->GetNumberOfRenders(), modelCopies = models->GetNumberOfCopies();
    const auto start = Clock::now();
    // Ticks at start + k · period, as the main window's 30 Hz QTimer: a frame that runs past the
    // next tick makes that tick fire as soon as it ends; ticks missed entirely are dropped, not
    // queued.
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(DisplayPeriod));
    auto next = start + period;
    while (std::chrono::duration<double>(Clock::now() - start).count() < Seconds()) {
      std::this_thread::sleep_until(next);
      next += period;
      const auto t0 = Clock::now();
      const double main0 = CpuMs(CLOCK_THREAD_CPUTIME_ID), process0 = CpuMs(CLOCK_PROCESS_CPUTIME_ID);
      rig->Session->Update();
      const auto tScene = Clock::now();
      // The views re-slice what moved as they render; the scheduler has the pictures of all but
      // the first view made on worker threads meanwhile.
      const std::array<double, 4> viewMsBefore = rig->ViewMs;
      const int picturesBefore = rig->Reslices();
      const int rendered = scheduler.RenderPendingViews();
      rig->WaitForFrame();
      const auto t1 = Clock::now();
      while (next + period <= t1) next += period;
      if (rendered == 0) continue;
      run.MainCpuMs += CpuMs(CLOCK_THREAD_CPUTIME_ID) - main0;
      run.ProcessCpuMs += CpuMs(CLOCK_PROCESS_CPUTIME_ID) - process0;
      run.FrameSumMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
      run.SceneMs += std::chrono::duration<double, std::milli>(tScene - t0).count();
      run.FrameMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      run.FrameAt.push_back(std::chrono::duration<double>(t0 - start).count());
      run.ViewsRendered.push_back(rendered);
      std::array<double, 4> viewMs{};
      for (size_t k = 0; k < 4; ++k) viewMs[k] = rig->ViewMs[k] - viewMsBefore[k];
      run.FrameViewMs.push_back(viewMs);
      run.FrameSceneMs.push_back(std::chrono::duration<double, std::milli>(tScene - t0).count());
      run.FramePictures.push_back(rig->Reslices() - picturesBefore);
    }
    run.Seconds = std::chrono::duration<double>(Clock::now() - start).count();
    run.Reslices = rig->Reslices() - reslices;
    run.PicturesAhead = rig->PicturesMadeAhead() - ahead;
    run.ModelLayerRenders = models->GetNumberOfRenders() - modelRenders;
    run.ModelLayerCopies = models->GetNumberOfCopies() - modelCopies;
    run.ViewMeanMs = rig->TakeViewMeanMs();
    rig->SavePicture(rp::bench::OutputDirectory() + "/viewer-4up-while-touching.png");  // what was drawn
    rig->StopHaptics();
    // The tool stopped: the next tick draws the moving views once more at full detail.
    scheduler.RenderPendingViews();
    scheduler.RenderPendingViews();
    rig->WaitForFrame();
    rig->SavePicture(rp::bench::OutputDirectory() + "/viewer-4up-still.png");
    rig->TakeViewMeanMs();
    Report(state, run);
    Runs.push_back(run);
  }
}

// Where a frame's time goes: each view rendered with one prop hidden at a time (the slices
// held still), the difference to rendering everything. Printed, and in viewer-frames.json.
nlohmann::json Breakdown;
void BM_Viewer4Up_Breakdown(benchmark::State& state) {
  Rig* rig = TheRig();
  if (!rig) {
    state.SkipWithError("no scene (see the message above)");
    return;
  }
  const char* names[4] = {"axial", "sagittal", "coronal", "3d"};
  for (auto _ : state) {
    for (int kind = 0; kind < 4; ++kind) {
      rp::View* view = rig->View(kind);
      // Median of interleaved renders with and without a prop (robust to a busy machine).
      auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.empty() ? 0.0 : v[v.size() / 2];
      };
      auto once = [&]() {
        const auto t0 = Clock::now();
        rig->Render(kind);
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      };
      std::vector<double> allTimes;
      for (int i = 0; i < 15; ++i) allTimes.push_back(once());
      const double all = median(allTimes);
      // A slice view whose slice moves (one step back and forth): its picture re-sliced before
      // the clock starts, so the time is the view's own (resampling, outlines, text, drawing).
      auto moving = [&]() {
        vtkRPSliceLogic* logic = rig->Controller->GetSliceLogic(static_cast<rp::ViewKind>(kind));
        static int step = 0;
        rig->Controller->MoveSlice(static_cast<rp::ViewKind>(kind), (step++ % 2) ? 1 : -1);
        logic->GetOutputPort()->GetProducer()->Update();
        return once();
      };
      nlohmann::json entry = {{"allMs", all}};
      std::vector<vtkRenderer*> renderers = {view->GetRenderer()};
      if (view->GetOverlayRenderer() != view->GetRenderer()) renderers.push_back(view->GetOverlayRenderer());
      {
        // The window's fixed cost (clear, blit, finish): every prop hidden.
        std::vector<vtkProp*> hidden;
        for (vtkRenderer* renderer : renderers) {
          vtkPropCollection* props = renderer->GetViewProps();
          props->InitTraversal();
          while (vtkProp* prop = props->GetNextProp()) {
            if (prop->GetVisibility()) {
              hidden.push_back(prop);
              prop->VisibilityOff();
            }
          }
        }
        std::vector<double> empty;
        for (int i = 0; i < 9; ++i) empty.push_back(once());
        for (vtkProp* prop : hidden) prop->VisibilityOn();
        entry["emptyMs"] = median(empty);
        std::cerr << "[viewer-bench] " << names[kind] << ": nothing drawn " << median(empty) << " ms\n";
      }
      // Each visible prop's cost: renders with it and without it, interleaved.
      auto propCosts = [&](const std::function<double()>& render, const char* key, const char* when) {
        for (vtkRenderer* renderer : renderers) {
          vtkPropCollection* props = renderer->GetViewProps();
          props->InitTraversal();
          std::vector<vtkProp*> list;
          while (vtkProp* prop = props->GetNextProp()) list.push_back(prop);
          for (vtkProp* prop : list) {
            if (!prop->GetVisibility()) continue;
            std::vector<double> with, without;
            for (int i = 0; i < 9; ++i) {
              with.push_back(render());
              prop->VisibilityOff();
              without.push_back(render());
              prop->VisibilityOn();
            }
            const double saved = median(with) - median(without);
            std::string label = prop->GetClassName();
            if (auto* actor = vtkActor::SafeDownCast(prop)) {
              if (auto* poly = vtkPolyData::SafeDownCast(actor->GetMapper() ? actor->GetMapper()->GetInputDataObject(0, 0) : nullptr)) {
                label += " (" + std::to_string(poly->GetNumberOfCells()) + " cells)";
              }
            }
            entry[key].push_back({{"prop", label}, {"savedMs", saved}});
            if (saved > 0.3) std::cerr << "[viewer-bench] " << names[kind] << when << ": " << label << " costs " << saved << " ms\n";
          }
        }
      };
      propCosts(once, "props", "");
      if (view->IsSlice()) {
        std::vector<double> movingTimes;
        for (int i = 0; i < 15; ++i) movingTimes.push_back(moving());
        entry["movingMs"] = median(movingTimes);
        std::cerr << "[viewer-bench] " << names[kind] << ": " << median(movingTimes) << " ms while its slice moves\n";
        propCosts(moving, "propsMoving", " while its slice moves");
      }
      Breakdown[names[kind]] = entry;
      std::cerr << "[viewer-bench] " << names[kind] << ": " << all << " ms still\n";
    }
  }
}

// A frame in which all three slices move, without the haptic loop: the slice point moved, the
// pictures re-sliced, the four views rendered. Beside the display-rate run's frames in which all
// three move it tells what the 1 kHz servo thread costs the frame on two cores.
void BM_Viewer4Up_MovingFrame(benchmark::State& state) {
  Rig* rig = TheRig();
  if (!rig) {
    state.SkipWithError("no scene (see the message above)");
    return;
  }
  std::vector<double> frames;
  double start[3];
  rig->Controller->GetSlicePointRAS(start);
  rp::RenderScheduler scheduler;  // as the display-rate run: pictures of later views made ahead
  for (int kind = 0; kind < 4; ++kind) {
    scheduler.AddView(rig->View(kind), [rig, kind]() { rig->Submit(kind); });
  }
  for (auto _ : state) {
    for (int i = 0; i < 40; ++i) {
      const auto t0 = Clock::now();
      // Off the voxel grid, as a tool moves them (on it, the re-slicing skips interpolating
      // along the normal): back and forth by 1.37 mm along each axis.
      const double offset = (i % 2 ? 1.0 : -1.0) * 0.685;
      const double point[3] = {start[0] + offset, start[1] + offset, start[2] + offset};
      rig->Controller->SetSlicePointRAS(point);
      scheduler.RenderPendingViews();
      rig->WaitForFrame();
      frames.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
  }
  rig->TakeViewMeanMs();
  const Percentiles p = Summarize(frames);
  state.counters["p50_ms"] = p.P50;
  state.counters["p95_ms"] = p.P95;
  std::cerr << "[viewer-bench] all three slices moving, no haptic loop: p50 " << p.P50 << " ms, p95 " << p.P95 << " ms\n";
}

BENCHMARK(BM_Viewer4Up_MovingFrame)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Viewer4Up_Breakdown)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Viewer4Up_Naive)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Viewer4Up_DisplayRate)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void WriteFigures(const std::string& out) {
  Rig* rig = OpenedRig;  // not made here: without a run (--benchmark_filter=NONE) no scene is needed
  nlohmann::json doc;
  doc["view"] = {{"width", ViewWidth}, {"height", ViewHeight}, {"layout", "4up 1400x1100 (four windows)"}};
  if (rig) {
    doc["scene"] = {{"file", rig->SceneFile},
                    {"trianglesVisible", Triangles(rig->Scene, true)},
                    {"trianglesAll", Triangles(rig->Scene, false)}};
  }
  std::vector<rp::bench::Series> series;
  for (const Run& run : Runs) {
    const Percentiles p = Summarize(run.FrameMs);
    doc["runs"][run.Name] = {{"frames", run.FrameMs.size()}, {"seconds", run.Seconds}, {"p50Ms", p.P50},
                             {"p95Ms", p.P95}, {"maxMs", p.Max}, {"meanMs", p.Mean},
                             {"fps", double(run.FrameMs.size()) / std::max(1e-9, run.Seconds)},
                             {"reslices", run.Reslices}, {"picturesMadeAhead", run.PicturesAhead}, {"targetP95Ms", 33.0},
                             {"slicesMovingFrames", FramesWithPictures(run).size()},
                             {"slicesMovingP95Ms", Summarize(FramesWithPictures(run)).P95},
                             {"modelLayerRenders", run.ModelLayerRenders}, {"modelLayerCopies", run.ModelLayerCopies},
                             {"mainCpuMsPerFrame", run.FrameSumMs > 0 ? run.MainCpuMs / double(std::max<size_t>(1, run.FrameMs.size())) : 0.0},
                             {"processCpuMsPerFrame", run.FrameSumMs > 0 ? run.ProcessCpuMs / double(std::max<size_t>(1, run.FrameMs.size())) : 0.0},
                             {"viewMeanMs", {{"axial", run.ViewMeanMs[0]}, {"sagittal", run.ViewMeanMs[1]},
                                             {"coronal", run.ViewMeanMs[2]}, {"3d", run.ViewMeanMs[3]}}}};
    rp::bench::Series s;
    s.Name = run.Name;
    s.X = run.FrameAt;
    s.Y = run.FrameMs;
    series.push_back(s);
    std::vector<std::vector<double>> rows;
    for (size_t i = 0; i < run.FrameMs.size(); ++i) {
      std::vector<double> row = {run.FrameAt[i], run.FrameMs[i], double(run.ViewsRendered[i])};
      for (size_t k = 0; k < 4; ++k) row.push_back(i < run.FrameViewMs.size() ? run.FrameViewMs[i][k] : std::nan(""));
      row.push_back(i < run.FrameSceneMs.size() ? run.FrameSceneMs[i] : std::nan(""));
      row.push_back(i < run.FramePictures.size() ? run.FramePictures[i] : std::nan(""));
      rows.push_back(row);
    }
    std::string error;
    std::string file = run.Name;
    std::replace(file.begin(), file.end(), ' ', '-');
    rp::bench::WriteCSV(out + "/viewer-frames-" + file + ".csv",
                        {"time_s", "frame_ms", "views_rendered", "axial_ms", "sagittal_ms", "coronal_ms", "3d_ms", "scene_ms", "pictures_made"},
                        rows, error);
  }
  rp::bench::Series target;
  target.Name = "33 ms (30 Hz)";
  target.X = {0, Seconds()};
  target.Y = {33, 33};
  series.push_back(target);
  if (!Breakdown.is_null()) doc["breakdown"] = Breakdown;
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpViewerBenchmark");  // the load after, the steal over the run
  std::string error;
  rp::bench::WriteFiguresJSON(out + "/viewer-frames.json", doc, error);
  rp::bench::ChartOptions chart{"4-up frame time while the haptic proxy moves (1400x1100, llvmpipe)", "time (s)",
                                "frame time (ms)"};
  rp::bench::WriteChartPNG(out + "/viewer-frame-times.png", series, chart, error);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const std::string out = rp::bench::OutputDirectory();
  benchmark::RunSpecifiedBenchmarks();
  WriteFigures(out);
  benchmark::Shutdown();
  return 0;
}
