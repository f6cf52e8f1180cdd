#include "rpHapticSession.h"

#include <cmath>

namespace rp {

void HapticForceSummary::Add(const HapticLogRecord& r) {
  ++this->Records;
  const double f = Norm(r.Force);
  this->MaxForce = std::fmax(this->MaxForce, f);
  if (r.Contacts > 0) {
    ++this->ContactTicks;
    this->SumForceInContact += f;
    const uint64_t ticks = ++this->TissueTicks[r.Label];
    if (ticks % 5 == 0) {  // every 5th contact tick is enough for a plot
      auto& curve = this->ForceCurves[r.Label];
      curve.first.push_back(Norm(r.Hip - r.Proxy));
      curve.second.push_back(f);
    }
  }
  this->ClampedTicks += (r.Flags & 2u) ? 1 : 0;
  this->WatchdogTicks += (r.Flags & 1u) ? 1 : 0;
  this->StallLimitedTicks += (r.Flags & 4u) ? 1 : 0;
}

HapticSession::HapticSession(HapticDevice& device) : Device(device) {}

HapticSession::~HapticSession() { this->Stop(); }

bool HapticSession::Start(vtkRPScene* scene, const Options& options, std::string& error) {
  if (this->Loop.Running()) {
    error = "haptics: already running";
    return false;
  }
  this->Scene = scene;
  this->Settings = options;
  this->WarningList.clear();
  this->ClampList.clear();
  if (this->Settings.Materials.Empty() && !LoadMaterialTable(this->Settings.Materials, error)) return false;
  this->Names = this->Settings.Materials.TissueNames();
  if (!this->Device.Open(error)) return false;
  this->Task = std::make_unique<HapticServo>(this->Device);
  HapticRenderer& renderer = this->Task->Renderer();
  renderer.SetOptions(options.Renderer);
  if (options.ToolPoints.empty() || !renderer.SetToolPoints(options.ToolPoints.data(), static_cast<int>(options.ToolPoints.size()))) {
    error = "haptics: a tool needs 1 to " + std::to_string(MaxToolPoints) + " points";
    return false;
  }
  this->Task->SetRampSeconds(options.RampSeconds);
  this->Task->Input().SetPosesInScene(options.PosesInScene);
  DeviceToScene xf;
  ReadDeviceToScene(scene, xf);
  this->Task->Input().SetDeviceToScene(xf);
  this->UpdateClamps(1.0 / options.Loop.RateHz);
  auto built = HapticScene::Build(CollectHapticMeshes(scene, this->WarningList), this->Settings.Materials,
                                  this->WarningList, error);
  if (!built) return false;
  this->Triangles = built->Tree.NumberOfTriangles();
  this->Task->Scenes().Publish(std::move(built));
  this->Builds.fetch_add(1);
  this->Signature = HapticMeshesSignature(scene);
  if (options.MakeConstraints) this->Task->Constraints().Publish(options.MakeConstraints());  // the fixtures
  this->Figures = HapticForceSummary{};
  if (options.Summarize) {
    auto onRecord = this->Writer.OnRecord;  // the owner's, kept
    this->Writer.OnRecord = [this, onRecord](const HapticLogRecord& r) {
      this->Figures.Add(r);
      if (onRecord) onRecord(r);
    };
  }
  if (!options.LogPath.empty() || this->Writer.OnRecord) {
    this->Task->EnableLog(true);
    if (!this->Writer.Start(this->Task->LogRing(), options.LogPath, this->Names, error)) return false;
  }
  if (!this->Loop.Start(this->Task.get(), options.Loop, error)) {
    this->Writer.Stop();
    return false;
  }
  return true;
}

void HapticSession::UpdateClamps(double period) {
  this->Period = period;
  this->Task->SetStabilityPeriod(period);
  DeviceToScene xf;
  ReadDeviceToScene(this->Scene, xf);
  const std::vector<MaterialClamp> clamps =
      ClampMaterials(this->Settings.Materials.Materials(), this->Device.Info(), period, xf.Scale);
  for (size_t i = 0; i < clamps.size(); ++i) {
    const bool wasClamped = i < this->ClampList.size() && this->ClampList[i].Clamped() &&
                            this->ClampList[i].RenderedStiffness <= clamps[i].RenderedStiffness * (1 + 1e-9);
    if (clamps[i].Clamped() && !wasClamped) this->WarningList.push_back(ClampWarning(clamps[i], this->Device.Info()));
  }
  this->ClampList = clamps;
}

void HapticSession::StartRebuild() {
  // Meshes are read here (VTK, main thread); the BVH is built on a worker.
  auto meshes = std::make_shared<std::vector<HapticMeshInput>>(CollectHapticMeshes(this->Scene, this->WarningList));
  this->BuildDone.store(false);
  this->Builder = std::thread([this, meshes] {
    std::vector<std::string> warnings;
    std::string error;
    this->Built = HapticScene::Build(*meshes, this->Settings.Materials, warnings, error);
    this->BuildDone.store(true, std::memory_order_release);
  });
}

bool HapticSession::Update() {
  if (!this->Task) return false;
  this->Task->Scenes().Collect();
  this->Task->Constraints().Collect();
  if (this->Builder.joinable() && this->BuildDone.load(std::memory_order_acquire)) {
    this->Builder.join();
    if (this->Built) {
      this->Triangles = this->Built->Tree.NumberOfTriangles();
      this->Task->Scenes().Publish(std::move(this->Built));
      this->Builds.fetch_add(1);
    }
  }
  const unsigned long signature = HapticMeshesSignature(this->Scene);
  if (signature != this->Signature && !this->Builder.joinable()) {
    this->Signature = signature;
    this->StartRebuild();
  }
  DeviceToScene xf;
  ReadDeviceToScene(this->Scene, xf);
  this->Task->Input().SetDeviceToScene(xf);
  // Colgate-Schenkel's T is the period the loop really keeps: follow the measured p99 once it
  // is 5 % past the last value used (enough ticks for a p99 first).
  const ServoStats stats = this->Loop.Stats();
  const double measured = stats.Period.P99Us * 1e-6;
  if (stats.Period.Count >= 1000 && measured > 1.05 * this->Period) this->UpdateClamps(measured);
  HapticState state;
  if (!this->Task->ReadState(state)) return false;
  UpdateToolNodes(this->Scene, state, this->Names);
  return true;
}

void HapticSession::Stop() {
  this->Loop.Stop();
  this->Writer.Stop();
  if (this->Builder.joinable()) this->Builder.join();
  this->Built.reset();
  if (this->Task) {
    this->Task->Scenes().Clear();
    this->Task->Constraints().Clear();
  }
  this->Device.Close();
}

}  // namespace rp
