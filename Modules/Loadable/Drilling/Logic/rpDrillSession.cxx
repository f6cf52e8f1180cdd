#include "rpDrillSession.h"

#include <vtkPolyData.h>

namespace rp {

DrillSession::DrillSession(HapticDevice& device) : Device(device) {}

DrillSession::~DrillSession() { this->Stop(); }

bool DrillSession::Start(DrillVolume& bone, const TriangleMesh& protectedSurface, std::unique_ptr<HapticScene> others,
                         const Options& options, std::string& error) {
  if (this->Running()) {
    error = "drilling: already running";
    return false;
  }
  if (bone.AllocatedBlocks() == 0) {
    error = "drilling: no bone to drill (build it first)";
    return false;
  }
  this->ProtectedTree = BVH{};
  if (!protectedSurface.Triangles.empty()) this->ProtectedTree.Build(protectedSurface);
  if (!this->Device.Open(error)) return false;
  this->Task = std::make_unique<DrillServo>(this->Device, bone, options.Servo);
  if (!this->ProtectedTree.Empty()) this->Task->SetProtectedSurface(&this->ProtectedTree);
  if (others) this->Task->Scenes().Publish(std::move(others));
  this->Task->SetControl(options.Control);
  this->Rpm = options.Control.Rpm;
  this->Frames = std::make_unique<DrillDisplay>(bone);
  this->FirstMesh = this->Frames->Initialize();
  this->PathPoints.clear();
  this->LastPathTime = -1;
  if (!options.RecordPath.empty()) {
    DrillRecordingInfo info{bone.Spacing(), options.Servo.FeedRate, options.Servo.ReferenceRpm, false};
    if (!this->Writer.Open(options.RecordPath, info, error)) return false;
  }
  this->Task->EnableRecords(true);
  if (!this->Frames->Start(options.DisplayHz, error)) return false;
  if (!this->Loop.Start(this->Task.get(), options.Loop, error)) {
    this->Frames->Stop();
    return false;
  }
  return true;
}

vtkSmartPointer<vtkPolyData> DrillSession::Update() {
  if (!this->Task) return nullptr;
  this->Task->Scenes().Collect();
  DrillRecord r;
  while (this->Task->Records().TryPop(r)) {
    this->Writer.Add(r, this->Rpm);
    if (r.Time >= this->LastPathTime + 0.01) {
      this->PathPoints.push_back(r.Proxy);
      this->LastPathTime = r.Time;
    }
  }
  return this->Frames ? this->Frames->TakeMesh() : nullptr;
}

void DrillSession::Stop() {
  this->Loop.Stop();
  if (this->Frames) this->Frames->Stop();
  if (this->Task) {
    this->Update();  // the last records
    this->Task->Scenes().Clear();
  }
  this->Writer.Close();
  if (this->Task) this->Device.Close();
}

}  // namespace rp
