#include "vtkRPDrillingLogic.h"

#include <algorithm>
#include <cctype>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "rpBlockMesher.h"
#include "rpDrillAnalytic.h"
#include "rpDrillSession.h"
#include "rpHapticSceneBridge.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSimulatedDevice.h"
#include "rpTunnelPicture.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

vtkStandardNewMacro(vtkRPDrillingLogic);

vtkRPDrillingLogic::vtkRPDrillingLogic() : Device(std::make_unique<rp::SimulatedDevice>()) {}

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

bool vtkRPDrillingLogic::BuildBone(const BoneChoice& choice, std::string& error) {
  if (this->Scene == nullptr) {
    error = "drilling: no scene";
    return false;
  }
  this->Stop();
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(this->Scene->GetNodeByID(choice.SegmentationID));
  if (segmentation == nullptr || segmentation->GetImageData() == nullptr) {
    error = "drilling: choose a segmentation";
    return false;
  }
  rp::MaterialTable table;
  if (!rp::LoadMaterialTable(table, error)) return false;
  const std::vector<rp::Material> materials = rp::DrillableMaterials(table);
  rp::DrillBoneSource source;
  source.Labels = rp::FromNode(segmentation);
  source.Spacing = choice.VoxelMm;
  std::vector<std::string> names;
  for (const std::string& id : choice.BoneSegments) {
    const auto* s = segmentation->GetSegmentByID(id);
    if (s == nullptr) {
      error = "drilling: no segment '" + id + "' in " + segmentation->GetName();
      return false;
    }
    source.BoneLabels.push_back(s->LabelValue);
    source.BoneTissues.push_back(s->TissueClass);
    names.push_back(s->Name.empty() ? s->ID : s->Name);
  }
  for (const std::string& id : choice.ProtectedSegments) {
    const auto* s = segmentation->GetSegmentByID(id);
    if (s == nullptr) {
      error = "drilling: no protected segment '" + id + "'";
      return false;
    }
    source.ProtectedLabels.push_back(s->LabelValue);
    source.ProtectedTissues.push_back(s->TissueClass);
  }
  if (!choice.CTVolumeID.empty()) {
    auto* ct = vtkRPScalarVolumeNode::SafeDownCast(this->Scene->GetNodeByID(choice.CTVolumeID));
    if (ct == nullptr) {
      error = "drilling: the CT volume is not in the scene";
      return false;
    }
    source.CT = rp::FromNode(ct);
  }
  auto bone = std::make_unique<rp::DrillVolume>();
  rp::DrillVolume protectedVolume;
  rp::DrillBoneReport report;
  if (!rp::BuildDrillBone(source, materials, *bone, &protectedVolume, report, error)) return false;
  this->Bone = std::move(bone);
  this->LastPath.clear();
  this->ProtectedSurface = report.HasProtected ? rp::ContourToTriangleMesh(protectedVolume) : rp::TriangleMesh{};
  this->Materials = materials;
  this->Report = report;
  this->BoneNames = names;
  // The drilled bone's model node (created once, its mesh replaced).
  auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID));
  if (model == nullptr) {
    vtkNew<vtkRPModelNode> node;
    this->Scene->AddNode(node);
    model = node;
    this->ModelID = node->GetID();
  }
  rp::BlockMesher mesher(*this->Bone);
  mesher.ContourAll();
  const int wasModifying = model->StartModify();
  std::string title = names.empty() ? "Bone" : names.front();
  for (size_t i = 1; i < names.size(); ++i) title += " + " + names[i];
  model->SetName(title + " (drilled)");
  model->SetTissueClass("bone");
  model->SetColor(0.95, 0.92, 0.82);
  model->SetHaptic(false);  // the burr renders it (voxels), not the Haptics module's mesh proxy
  model->SetPolyData(rp::DrillDisplay::Assemble(mesher));
  model->EndModify(wasModifying);
  this->Modified();
  return true;
}

bool vtkRPDrillingLogic::StartSimulated(std::string& error) {
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
  for (rp::HapticMeshInput& m : rp::CollectHapticMeshes(this->Scene, warnings)) {
    bool drilled = false;
    for (const std::string& name : this->BoneNames) drilled = drilled || lower(m.Name).rfind(lower(name), 0) == 0;
    if (!drilled) meshes.push_back(std::move(m));
  }
  std::unique_ptr<rp::HapticScene> others;
  if (!meshes.empty()) {
    rp::MaterialTable table;
    if (!rp::LoadMaterialTable(table, error)) return false;
    others = rp::HapticScene::Build(meshes, table, warnings, error);
    if (!others) return false;
  }
  rp::DrillSession::Options options;
  options.Control = this->Control;
  options.RecordPath = this->RecordPath;
  this->Session = std::make_unique<rp::DrillSession>(*this->Device);
  if (!this->Session->Start(*this->Bone, this->ProtectedSurface, std::move(others), options, error)) {
    this->Session.reset();
    return false;
  }
  rp::DeviceToScene xf;
  rp::ReadDeviceToScene(this->Scene, xf);
  this->Session->Servo().SetDeviceToScene(xf);
  return true;
}

void vtkRPDrillingLogic::Stop() {
  if (this->Session) {
    this->Session->Stop();
    this->LastPath = this->Session->Path();
  }
  this->Session.reset();
}

bool vtkRPDrillingLogic::IsRunning() const { return this->Session && this->Session->Running(); }

void vtkRPDrillingLogic::SetBurrOn(bool on) {
  this->Control.BurrOn = on;
  if (this->Session) this->Session->Servo().SetControl(this->Control);
}

void vtkRPDrillingLogic::SetBurrRadius(double mm) {
  this->Control.Radius = mm;
  if (this->Session) this->Session->Servo().SetControl(this->Control);
}

void vtkRPDrillingLogic::SetRpm(double rpm) {
  this->Control.Rpm = rpm;
  if (this->Session) {
    this->Session->Servo().SetControl(this->Control);
    this->Session->SetRpm(rpm);
  }
}

void vtkRPDrillingLogic::Undo() {
  if (this->Session) this->Session->Servo().RequestUndo();
}

void vtkRPDrillingLogic::ResetBone() {
  if (this->Session) this->Session->Servo().RequestReset();
}

void vtkRPDrillingLogic::SetSimulatedBurrPosition(const double ras[3]) {
  rp::DeviceToScene xf;
  rp::ReadDeviceToScene(this->Scene, xf);
  const double scale = xf.Scale > 0 ? xf.Scale : 1.0;
  rp::Pose pose;
  pose.T = xf.DeviceToRAS.RotateInverse(rp::Vec3{ras[0], ras[1], ras[2]} - xf.DeviceToRAS.T) / scale;
  this->Device->SetManualPose(pose);
}

bool vtkRPDrillingLogic::Update() {
  if (!this->Session) return false;
  if (!this->FollowedID.empty()) {
    if (auto* node = vtkRPTransformableNode::SafeDownCast(this->Scene->GetNodeByID(this->FollowedID))) {
      vtkNew<vtkMatrix4x4> toWorld;
      node->GetMatrixTransformToWorld(toWorld);
      const double tip[3] = {toWorld->GetElement(0, 3), toWorld->GetElement(1, 3), toWorld->GetElement(2, 3)};
      this->SetSimulatedBurrPosition(tip);
    }
  }
  rp::DeviceToScene xf;
  rp::ReadDeviceToScene(this->Scene, xf);
  this->Session->Servo().SetDeviceToScene(xf);
  bool changed = false;
  if (vtkSmartPointer<vtkPolyData> mesh = this->Session->Update()) {
    if (auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->ModelID))) {
      model->SetPolyData(mesh);  // one pointer swap; the display thread built it
      changed = true;
    }
  }
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
  picture.Path = this->Session ? this->Session->Path() : this->LastPath;
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
