#include "vtkRPDrillingLogic.h"

#include <algorithm>
#include <cctype>
#include <chrono>

#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "rpDrillAnalytic.h"
#include "rpFixtureConstraint.h"
#include "rpHapticSceneBridge.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSimulatedDevice.h"
#include "rpTunnelPicture.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

vtkStandardNewMacro(vtkRPDrillingLogic);

vtkRPDrillingLogic::vtkRPDrillingLogic()
    : Planning(vtkSmartPointer<vtkRPPlanningLogic>::New()), Device(std::make_unique<rp::SimulatedDevice>()) {}

bool vtkRPDrillingLogic::SetPlanFixtures(const rp::PlanFixtureChoice& choice, std::string& error) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  this->Planning->SetScene(this->Scene);
  std::shared_ptr<const rp::FixtureSet> set = this->Planning->MakePlanFixtures(choice, error);
  if (!set) return false;  // refused: the set in use stays
  this->PlanFixtures = set;
  rp::InstallFixtures(this->PlanFixtures, this->MakeConstraints, this->IsRunning() ? &this->Session->Servo().Constraints() : nullptr);
  return true;
}

vtkRPDrillingLogic::~vtkRPDrillingLogic() { this->Stop(); }

void vtkRPDrillingLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Bone: " << (this->Bone ? std::to_string(this->Report.StoredBlocks) + " blocks" : "none") << "\n";
  os << indent << "Running: " << (this->IsRunning() ? "yes" : "no") << "\n";
}

std::vector<std::string> vtkRPDrillingLogic::GetTissueNames() const {
  std::vector<std::string> names;
  for (const rp::Material& m : this->Materials) names.push_back(m.Tissue);
  return names;
}

vtkPolyData* vtkRPDrillingLogic::GetDrilledMesh() const {
  auto* model = this->Scene ? vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID)) : nullptr;
  return model ? model->GetPolyData() : nullptr;
}

bool vtkRPDrillingLogic::LoadMaterials(std::string& error) {
  if (!rp::LoadMaterialTable(this->Table, error, this->MaterialsPath)) return false;
  this->Materials = rp::DrillableMaterials(this->Table);
  if (this->Materials.empty()) {
    error = this->Table.Source() + " has no drillable material (no \"hardness\")";
    return false;
  }
  return true;
}

bool vtkRPDrillingLogic::BuildBone(const BoneChoice& choice, std::string& error) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(this->Scene->GetNodeByID(choice.SegmentationID));
  if (segmentation == nullptr || segmentation->GetImageData() == nullptr) {
    error = "drilling: choose a segmentation";
    return false;
  }
  rp::DrillBoneSource source;
  source.Labels = rp::FromNode(segmentation);
  source.Spacing = choice.VoxelMm;
  rp::DrillSegments bone, guarded;
  if (!rp::FindDrillSegments(segmentation, choice.BoneSegments, bone, error) ||
      !rp::FindDrillSegments(segmentation, choice.ProtectedSegments, guarded, error)) {
    error = "drilling: " + error;
    return false;
  }
  source.BoneLabels = bone.Labels;
  source.BoneTissues = bone.Tissues;
  source.ProtectedLabels = guarded.Labels;
  source.ProtectedTissues = guarded.Tissues;
  if (!choice.CTVolumeID.empty()) {
    auto* ct = vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(choice.CTVolumeID));
    if (ct == nullptr) {
      error = "drilling: the CT volume is not in the scene";
      return false;
    }
    source.CT = rp::FromNode(ct);
  }
  return this->BuildBone(source, bone.Names, error);
}

bool vtkRPDrillingLogic::BuildBone(const rp::DrillBoneSource& source, const std::vector<std::string>& boneNames,
                                   std::string& error, const rp::ProgressCallback& progress) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  this->Stop();
  this->Session.reset();  // it holds the bone and its display
  if (!this->LoadMaterials(error)) return false;
  auto bone = std::make_unique<rp::DrillVolume>();
  rp::DrillVolume protectedVolume;
  rp::DrillBoneReport report;
  if (!rp::BuildDrillBone(source, this->Materials, *bone, &protectedVolume, report, error, progress)) return false;
  this->Display.reset();
  this->Bone = std::move(bone);
  this->ProtectedSurface = report.HasProtected ? rp::ContourToTriangleMesh(protectedVolume) : rp::TriangleMesh{};
  this->Report = report;
  return this->ShowBone(boneNames);
}

bool vtkRPDrillingLogic::BuildBlockBone(const rp::Vec3& lo, const rp::Vec3& hi, double shellMm, double voxelMm,
                                        std::string& error) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  this->Stop();
  this->Session.reset();
  if (!this->LoadMaterials(error)) return false;
  const auto start = std::chrono::steady_clock::now();
  const uint8_t bone = rp::FindDrillMaterial(this->Materials, "bone");
  const uint8_t cortical = bone ? bone : 1;
  const uint8_t trabecular = rp::FindDrillMaterial(this->Materials, "trabecular bone");
  if (shellMm > 0 && trabecular == 0) {
    error = "a cortical shell needs a drillable \"trabecular bone\" in the material table";
    return false;
  }
  this->Display.reset();
  this->Bone = std::make_unique<rp::DrillVolume>();
  if (!rp::BuildAnalyticBone(rp::BlockBone(lo, hi, cortical, shellMm, trabecular), voxelMm, this->Materials, *this->Bone,
                             error)) {
    this->Bone.reset();
    return false;
  }
  rp::DrillBoneReport report;
  report.GridVoxels = this->Bone->Grid().VoxelCount();
  report.StoredBlocks = this->Bone->AllocatedBlocks();
  report.MemoryMB = this->Bone->MemoryBytes() / 1e6;
  report.VolumeMm3 = this->Bone->OriginalVolumes();
  report.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  auto box = std::make_shared<rp::MeshSignedDistance>();  // the block's surface (breach of an execution)
  if (box->Build(rp::shapes::Box(lo, hi), error)) report.BoneSurface = box;
  this->Report = report;
  this->ProtectedSurface = rp::TriangleMesh{};
  return this->ShowBone({"block"});
}

// The bone's display (contoured once, kept across sessions) and its model node (created once,
// its mesh replaced).
bool vtkRPDrillingLogic::ShowBone(const std::vector<std::string>& boneNames) {
  this->Display = std::make_unique<rp::DrillDisplay>(*this->Bone);
  this->BoneNames = boneNames;
  auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID));
  if (model == nullptr) {
    vtkNew<vtkRPModelNode> node;
    this->Scene->AddNode(node);
    model = node;
    this->ModelID = node->GetID();
  }
  const int wasModifying = model->StartModify();
  std::string title = boneNames.empty() ? "Bone" : boneNames.front();
  for (size_t i = 1; i < boneNames.size(); ++i) title += " + " + boneNames[i];
  model->SetName(title + " (drilled)");
  model->SetTissueClass("bone");
  model->SetColor(0.95, 0.92, 0.82);
  model->SetHaptic(false);  // the burr renders it (voxels), not the Haptics module's mesh proxy
  model->SetPolyData(this->Display->Initialize());
  model->EndModify(wasModifying);
  this->Placed = false;
  this->Modified();
  return true;
}

void vtkRPDrillingLogic::SetSimulatedTrajectory(std::shared_ptr<const rp::Trajectory> path) {
  this->Device->SetTrajectory(std::move(path));
}

void vtkRPDrillingLogic::SetSimulatedHand(const rp::HandNoise& noise, const rp::HandImpedance& impedance) {
  this->HasHand = true;
  this->HandTremor = noise;
  this->HandGrip = impedance;
}

void vtkRPDrillingLogic::PlaceBurr(const rp::Vec3& center, const rp::DrillControl& control) {
  this->Placed = true;
  this->PlacedAt = center;
  this->PlacedControl = control;
}

// A new session on the bone: the scene's other haptic models (when touched), the recording, the
// burr placed; the simulated device's poses are in RAS already (the panel, a followed tool, a
// path in RAS): HapticDeviceToRAS only gives the workspace scale of the device it stands for.
bool vtkRPDrillingLogic::PrepareSession(bool keepRecords, std::string& error) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  if (!this->Bone) {
    error = "drilling: build the bone first (choose a segmentation and its bone segment)";
    return false;
  }
  if (this->IsRunning()) {
    error = "drilling: already running";
    return false;
  }
  // The scene's other haptic models are touched with the Haptics module's god-object in the same
  // tick; the drilled bone's own models (named after its segments) are left to the burr.
  std::vector<std::string> warnings;
  std::vector<rp::HapticMeshInput> meshes;
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
  };
  if (this->TouchOthers) {
    for (rp::HapticMeshInput& m : rp::CollectHapticMeshes(this->Scene, warnings)) {
      bool drilled = false;
      for (const std::string& name : this->BoneNames) drilled = drilled || lower(m.Name).rfind(lower(name), 0) == 0;
      if (!drilled) meshes.push_back(std::move(m));
    }
  }
  std::unique_ptr<rp::HapticScene> others;
  if (!meshes.empty()) {
    others = rp::HapticScene::Build(meshes, this->Table, warnings, error);
    if (!others) return false;
  }
  rp::DrillSession::Options options;
  options.Servo = this->ServoSettings;
  options.Control = this->Control;
  options.Loop = this->LoopSettings;
  options.RecordPath = this->RecordPath;
  options.StartCut = this->Placed && this->PlacedControl.BurrOn;
  options.KeepRecords = keepRecords;
  options.MakeConstraints = this->MakeConstraints;
  this->Session.reset();
  this->Device->SetHand(this->HasHand ? std::make_unique<rp::SimulatedHand>(this->HandTremor, this->HandGrip,
                                                                            this->Device->Info().PhysicalDamping)
                                      : nullptr);
  this->Session = std::make_unique<rp::DrillSession>(*this->Device, *this->Bone, *this->Display);
  if (!this->Session->Prepare(options, this->ProtectedSurface, std::move(others), error)) {
    this->Session.reset();
    return false;
  }
  this->Session->Servo().Input().SetPosesInScene(true);
  rp::DeviceToScene xf;
  rp::ReadDeviceToScene(this->Scene, xf);
  this->Session->Servo().Input().SetDeviceToScene(xf);
  if (this->Placed) {
    this->Session->Servo().PlaceBurr(this->PlacedAt, this->PlacedControl);
    // The placed cut belongs to the bone the run starts from (not to the run's display frames).
    if (this->Display->CatchUp() > 0) this->SwapMesh(rp::DrillDisplay::Assemble(this->Display->Mesher()));
    this->Placed = false;
  }
  return true;
}

bool vtkRPDrillingLogic::StartSimulated(std::string& error) {
  if (!this->PrepareSession(false, error)) return false;
  if (!this->Session->Start(error)) {
    this->Session.reset();
    return false;
  }
  return true;
}

bool vtkRPDrillingLogic::RunSimulated(const rp::DrillRunOptions& run, rp::DrillRunResult& result, std::string& error) {
  if (!this->PrepareSession(true, error)) return false;
  rp::DrillRunOptions options = run;
  options.OnMesh = [this, &run](vtkPolyData* mesh) {
    this->SwapMesh(mesh);
    if (run.OnMesh) run.OnMesh(mesh);
  };
  return this->Session->Run(options, result, error);
}

bool vtkRPDrillingLogic::SwapMesh(vtkPolyData* mesh) {
  auto* model = this->Scene ? vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID)) : nullptr;
  if (mesh == nullptr || model == nullptr) return false;
  model->SetPolyData(mesh);  // one pointer swap; the display built it
  return true;
}

void vtkRPDrillingLogic::Stop() {
  if (this->Session) this->SwapMesh(this->Session->Stop());  // the last cuts
}

bool vtkRPDrillingLogic::IsRunning() const { return this->Session && this->Session->Running(); }

void vtkRPDrillingLogic::SetBurrOn(bool on) {
  this->Control.BurrOn = on;
  if (this->Session) this->Session->SetControl(this->Control);
}

void vtkRPDrillingLogic::SetBurrRadius(double mm) {
  this->Control.Radius = mm;
  if (this->Session) this->Session->SetControl(this->Control);
}

void vtkRPDrillingLogic::SetRpm(double rpm) {
  this->Control.Rpm = rpm;
  if (this->Session) this->Session->SetControl(this->Control);
}

void vtkRPDrillingLogic::Undo() {
  if (this->Session) this->Session->Servo().RequestUndo();
}

void vtkRPDrillingLogic::ResetBone() {
  if (this->Session) this->Session->Servo().RequestReset();
}

void vtkRPDrillingLogic::SetSimulatedBurrPosition(const double ras[3]) {
  rp::Pose pose;
  pose.T = rp::Vec3{ras[0], ras[1], ras[2]};
  this->Device->SetManualPose(pose);
}

bool vtkRPDrillingLogic::Update() {
  if (!this->Session || !this->Session->Running()) return false;
  rp::Pose followed;
  if (!this->FollowedID.empty() && rp::ReadToolPose(this->Scene, this->FollowedID, followed))
    this->Device->SetManualPose(followed);  // the tracked drill's tip, in RAS as the servo takes it
  rp::DeviceToScene xf;
  rp::ReadDeviceToScene(this->Scene, xf);
  this->Session->Servo().Input().SetDeviceToScene(xf);
  const bool changed = this->SwapMesh(this->Session->Update());
  rp::DrillState s;
  if (this->Session->Servo().ReadState(s)) {
    // The burr in the views, as the Haptics module shows its tool.
    rp::HapticState h;
    h.Time = s.Time;
    h.Hip = s.Hip;
    h.Proxy = s.Proxy;
    h.Force = s.Force;
    h.Contacts = s.Contact ? 1 : 0;
    h.Label = s.Material;
    h.DeviceError = s.DeviceError;
    h.Stylus.T = s.Hip;
    rp::UpdateToolNodes(this->Scene, h, this->GetTissueNames());
  }
  return changed;
}

bool vtkRPDrillingLogic::ReadState(rp::DrillState& state) const {
  return this->Session && this->Session->Servo().ReadState(state);
}

bool vtkRPDrillingLogic::SaveTunnelPicture(const std::string& path, std::string& error) {
  auto* model = this->Scene ? vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID)) : nullptr;
  if (!this->Bone || model == nullptr) {
    error = "drilling: no drilled bone";
    return false;
  }
  rp::TunnelPicture picture;
  picture.Bone = model->GetPolyData();
  picture.Volume = this->Bone.get();
  picture.Materials = this->Materials;
  if (this->Session) picture.Path = this->Session->Path();
  if (picture.Path.size() < 2) {
    error = "drilling: nothing drilled yet (no burr path)";
    return false;
  }
  // The stroke's axis: from where the path began to the point of it farthest from there.
  picture.From = picture.Path.front();
  picture.To = picture.From;
  for (const rp::Vec3& p : picture.Path)
    if (rp::Norm(p - picture.From) > rp::Norm(picture.To - picture.From)) picture.To = p;
  picture.Radius = this->Control.Radius;
  if (!this->ProtectedSurface.Triangles.empty()) picture.Protected = rp::TriangleMeshToPolyData(this->ProtectedSurface);
  picture.Title = model->GetName();
  return rp::WriteTunnelPicture(path, picture, error);
}
