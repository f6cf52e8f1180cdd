#include "vtkRPTrackingLogic.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>

#include "rpImageTable.h"
#include "rpNdiRom.h"
#include "rpPolarisSimulator.h"
#include "rpPlusSequenceFile.h"
#include "rpToolDefinition.h"
#include "rpTransformNames.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"

vtkStandardNewMacro(vtkRPTrackingLogic);

vtkRPTrackingLogic::vtkRPTrackingLogic() = default;
vtkRPTrackingLogic::~vtkRPTrackingLogic() {
  for (auto& [id, source] : this->Sources)
    if (source.Owned) source.Owned->Stop();
}

void vtkRPTrackingLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Sources: " << this->Sources.size() << "\n"
     << indent << "StaleTimeout: " << this->StaleTimeout << "\n"
     << indent << "AutoCreateNodes: " << this->AutoCreateNodes << "\n";
}

void vtkRPTrackingLogic::SetScene(vtkRPScene* scene) {
  this->Scene = scene;
  for (auto& [id, source] : this->Sources) {
    for (Tool& t : source.Tools) t.NodeID.clear();
    for (Image& i : source.Streams) i.NodeID.clear();
  }
  this->DerivedNodeIDs.clear();
}

int vtkRPTrackingLogic::Connect(const rp::PoseSourceConfig& config, std::string& error) {
  try {
    return this->AddSource(rp::PoseSourceRegistry::Create(config), error);
  } catch (const std::exception& e) {
    error = e.what();
    return -1;
  }
}

int vtkRPTrackingLogic::AddSource(std::unique_ptr<rp::PoseSource> source, std::string& error) {
  if (!source) {
    error = "no source";
    return -1;
  }
  if (!source->Start(error)) return -1;
  const int id = this->AddPoseTable(&source->Poses(), source->Images());
  this->Sources[id].Owned = std::move(source);
  return id;
}

rp::PoseSource* vtkRPTrackingLogic::GetSource(int id) const {
  const auto it = this->Sources.find(id);
  return it == this->Sources.end() ? nullptr : it->second.Owned.get();
}

void vtkRPTrackingLogic::RemoveSource(int id) {
  const auto it = this->Sources.find(id);
  if (it == this->Sources.end()) return;
  if (it->second.Owned) it->second.Owned->Stop();
  this->Sources.erase(it);
}

int vtkRPTrackingLogic::AddPoseTable(const rp::ToolPoseTable* poses, const rp::ImageTable* images) {
  const int id = this->NextSourceId++;
  Source& s = this->Sources[id];
  s.Table = poses;
  s.Images = images;
  return id;
}

std::vector<int> vtkRPTrackingLogic::GetReadyFds() const {
  std::vector<int> fds;
  for (const auto& [id, source] : this->Sources)
    if (source.Owned && source.Owned->ReadyFd() >= 0) fds.push_back(source.Owned->ReadyFd());
  return fds;
}

vtkRPTrackedToolNode* vtkRPTrackingLogic::NodeFor(Tool& tool) {
  if (!this->Scene) return nullptr;
  // By ID every time: a node deleted by the user simply is not found.
  auto* node = vtkRPTrackedToolNode::SafeDownCast(tool.NodeID.empty() ? nullptr : this->Scene->GetNodeByID(tool.NodeID));
  if (node) return node;
  tool.NodeID.clear();
  for (vtkRPNode* candidate : this->Scene->GetNodesByName(tool.NodeName)) {
    if (auto* existing = vtkRPTrackedToolNode::SafeDownCast(candidate)) {
      tool.NodeID = existing->GetID();
      return existing;
    }
  }
  if (!this->AutoCreateNodes) return nullptr;
  vtkNew<vtkRPTrackedToolNode> created;
  created->SetName(tool.NodeName);
  this->Scene->AddNode(created);
  tool.NodeID = created->GetID();
  return created;
}

vtkRPScalarVolumeNode* vtkRPTrackingLogic::VolumeFor(Image& image) {
  if (!this->Scene) return nullptr;
  auto* node = vtkRPScalarVolumeNode::SafeDownCast(image.NodeID.empty() ? nullptr : this->Scene->GetNodeByID(image.NodeID));
  if (node) return node;
  image.NodeID.clear();
  for (vtkRPNode* candidate : this->Scene->GetNodesByName(image.NodeName)) {
    if (auto* existing = vtkRPScalarVolumeNode::SafeDownCast(candidate)) {
      image.NodeID = existing->GetID();
      return existing;
    }
  }
  return nullptr;
}

void vtkRPTrackingLogic::WriteNode(vtkRPTrackedToolNode* node, const rp::ToolPose& pose, int status, double errorRMS) {
  const int wasModifying = node->StartModify();
  if (status == vtkRPTrackedToolNode::StatusOK || status == vtkRPTrackedToolNode::StatusOutOfVolume) {
    double m[16];
    pose.ToMatrix(m);
    node->SetMatrixTransformToParent(m);
  }
  node->SetStatus(status);
  node->SetTimestamp(pose.Timestamp);
  node->SetErrorRMS(errorRMS);
  node->EndModify(wasModifying);
}

namespace {
int StatusOf(const rp::ToolPose& pose) {
  switch (pose.State) {
    case rp::ToolState::OK: return vtkRPTrackedToolNode::StatusOK;
    case rp::ToolState::Missing: return vtkRPTrackedToolNode::StatusMissing;
    case rp::ToolState::OutOfVolume: return vtkRPTrackedToolNode::StatusOutOfVolume;
    case rp::ToolState::Disabled: return vtkRPTrackedToolNode::StatusDisabled;
  }
  return vtkRPTrackedToolNode::StatusUnknown;
}

int VtkScalarType(uint8_t type) {
  switch (type) {
    case rp::ImageFrame::Int8: return VTK_SIGNED_CHAR;
    case rp::ImageFrame::UInt8: return VTK_UNSIGNED_CHAR;
    case rp::ImageFrame::Int16: return VTK_SHORT;
    case rp::ImageFrame::UInt16: return VTK_UNSIGNED_SHORT;
    case rp::ImageFrame::Int32: return VTK_INT;
    case rp::ImageFrame::UInt32: return VTK_UNSIGNED_INT;
    case rp::ImageFrame::Float32: return VTK_FLOAT;
    case rp::ImageFrame::Float64: return VTK_DOUBLE;
  }
  return VTK_VOID;
}
}  // namespace

void vtkRPTrackingLogic::WriteVolume(vtkRPScalarVolumeNode* node, const rp::ImageFrame& frame) {
  const int wasModifying = node->StartModify();
  vtkImageData* image = node->GetImageData();
  int dims[3] = {0, 0, 0};
  if (image) image->GetDimensions(dims);
  const bool first = !image || image->GetNumberOfPoints() == 0;
  const bool sameLayout = image && dims[0] == frame.Dimensions[0] && dims[1] == frame.Dimensions[1] &&
                          dims[2] == frame.Dimensions[2] && image->GetScalarType() == VtkScalarType(frame.ScalarType) &&
                          image->GetNumberOfScalarComponents() == frame.Components;
  if (!sameLayout) {  // a new size or type: a new image (once; frames after it reuse it)
    vtkNew<vtkImageData> fresh;
    fresh->SetDimensions(frame.Dimensions);
    fresh->AllocateScalars(VtkScalarType(frame.ScalarType), frame.Components);
    node->SetImageData(fresh);
    image = fresh;
  }
  std::memcpy(image->GetScalarPointer(), frame.Pixels.data(), frame.Pixels.size());  // IJK order, i fastest: VTK's
  image->Modified();
  vtkNew<vtkMatrix4x4> ijkToRas;
  ijkToRas->DeepCopy(frame.IjkToRas);
  node->SetIJKToRASMatrix(ijkToRas);
  if (first || !sameLayout) node->SetWindowLevelFromScalarRange();
  node->Modified();  // new voxels
  node->EndModify(wasModifying);
}

int vtkRPTrackingLogic::UpdateTools(Source& source, double now, std::vector<const Tool*>& all,
                                    std::vector<const Tool*>& changed, const Tool*& reference) {
  int modified = 0;
  const int count = source.Table ? source.Table->Count() : 0;
  if (static_cast<int>(source.Tools.size()) < count) {
    const size_t old = source.Tools.size();
    source.Tools.resize(static_cast<size_t>(count));
    for (size_t i = old; i < source.Tools.size(); ++i) source.Tools[i].NodeName = source.Table->Name(static_cast<int>(i));
  }
  for (int slot = 0; slot < count; ++slot) {
    Tool& tool = source.Tools[static_cast<size_t>(slot)];
    const auto& sample = source.Reader.Poll(*source.Table, slot);
    int status = tool.Status;
    if (sample.Fresh) {
      const double dt = now - tool.LastFreshTime;
      const uint64_t n = sample.Received - tool.LastReceived;
      if (tool.LastFreshTime > 0 && dt > 0) tool.RateHz = 0.8 * tool.RateHz + 0.2 * (static_cast<double>(n) / dt);
      tool.LastFreshTime = now;
      tool.LastReceived = sample.Received;
      tool.Pose = sample.Pose;
      tool.HasPose = true;
      if (sample.Pose.State == rp::ToolState::OK || sample.Pose.State == rp::ToolState::OutOfVolume) {
        tool.ValidPose = sample.Pose;
        tool.HasValidPose = true;
      }
      tool.Latency = now - sample.Pose.ReceiveTime;
      tool.LatencySum += tool.Latency;
      tool.MaxLatency = std::max(tool.MaxLatency, tool.Latency);
      ++tool.Updates;
      tool.ErrorRMS = sample.Pose.Error;
      status = StatusOf(sample.Pose);
    } else if (tool.HasPose && now - tool.Pose.ReceiveTime > this->StaleTimeout) {
      status = vtkRPTrackedToolNode::StatusStale;  // the source went quiet
    }
    if (!tool.HasPose) continue;
    all.push_back(&tool);
    if (!this->ReferenceName.empty() && tool.NodeName == this->ReferenceName) reference = &tool;
    if (!sample.Fresh && status == tool.Status) continue;  // nothing new: leave the node alone
    tool.Status = status;
    changed.push_back(&tool);
    if (vtkRPTrackedToolNode* node = this->NodeFor(tool)) {
      this->WriteNode(node, tool.Pose, status, tool.ErrorRMS);
      ++modified;
    }
  }
  return modified;
}

int vtkRPTrackingLogic::UpdateImages(Source& source, double now) {
  int modified = 0;
  const int count = source.Images ? source.Images->Count() : 0;
  if (static_cast<int>(source.Streams.size()) < count) {
    const size_t old = source.Streams.size();
    source.Streams.resize(static_cast<size_t>(count));
    for (size_t i = old; i < source.Streams.size(); ++i) source.Streams[i].NodeName = source.Images->Name(static_cast<int>(i));
  }
  for (int slot = 0; slot < count; ++slot) {
    Image& stream = source.Streams[static_cast<size_t>(slot)];
    const rp::ImageFrame* frame = source.Images->TakeNewest(slot, &stream.Published);  // one reader: this thread
    if (!frame) continue;
    std::copy(frame->Dimensions, frame->Dimensions + 3, stream.Dimensions);
    stream.Latency = now - frame->ReceiveTime;
    if (vtkRPScalarVolumeNode* node = this->VolumeFor(stream)) {
      this->WriteVolume(node, *frame);
    } else if (this->AutoCreateNodes) {
      // Filled before it joins the scene: views and modules see a complete volume when it appears.
      vtkNew<vtkRPScalarVolumeNode> created;
      created->SetName(stream.NodeName);
      this->WriteVolume(created, *frame);
      this->Scene->AddNode(created);
      stream.NodeID = created->GetID();
    } else {
      continue;
    }
    ++stream.Shown;
    ++modified;
  }
  return modified;
}

int vtkRPTrackingLogic::UpdateNodes(double now) {
  for (auto& [id, source] : this->Sources)
    if (source.Owned) source.Owned->DrainReady();
  if (!this->Scene) return 0;
  int modified = 0;
  this->Scene->StartBatchProcess();
  const Tool* reference = nullptr;
  std::vector<const Tool*> all, changed;
  for (auto& [id, source] : this->Sources) {
    modified += this->UpdateTools(source, now, all, changed, reference);
    modified += this->UpdateImages(source, now);
  }
  // ToolToReference for every other tool.
  if (reference) {
    const bool referenceChanged = std::find(changed.begin(), changed.end(), reference) != changed.end();
    for (const Tool* tool : all) {
      if (tool == reference) continue;
      if (!referenceChanged && std::find(changed.begin(), changed.end(), tool) == changed.end()) continue;
      const std::string name = rp::TransformName(rp::ToolNameOf(tool->NodeName), "Reference");
      rp::ToolPose relative = rp::ToolToReference(tool->Pose, reference->Pose);
      int status = StatusOf(relative);
      if (tool->Status == vtkRPTrackedToolNode::StatusStale || reference->Status == vtkRPTrackedToolNode::StatusStale)
        status = vtkRPTrackedToolNode::StatusStale;
      std::string& id = this->DerivedNodeIDs[name];
      Tool derived;
      derived.NodeName = name;
      derived.NodeID = id;
      if (vtkRPTrackedToolNode* node = this->NodeFor(derived)) {
        id = derived.NodeID;
        this->WriteNode(node, relative, status, tool->ErrorRMS);
        ++modified;
      }
    }
  }
  this->Scene->EndBatchProcess();
  return modified;
}

std::vector<vtkRPTrackingLogic::ToolStatistics> vtkRPTrackingLogic::GetToolStatistics() const {
  std::vector<ToolStatistics> out;
  for (const auto& [id, source] : this->Sources) {
    for (size_t slot = 0; slot < source.Tools.size(); ++slot) {
      const Tool& t = source.Tools[slot];
      ToolStatistics s;
      s.NodeName = t.NodeName;
      s.NodeID = t.NodeID;
      s.Status = t.Status;
      s.Frames = source.Table->Counts(static_cast<int>(slot));
      s.Dropped = source.Reader.Last(static_cast<int>(slot)).Dropped;
      s.RateHz = t.RateHz;
      s.LatencySeconds = t.Latency;
      s.MeanLatencySeconds = t.Updates ? t.LatencySum / static_cast<double>(t.Updates) : 0;
      s.MaxLatencySeconds = t.MaxLatency;
      s.ErrorRMS = t.ErrorRMS;
      s.HasPose = t.HasValidPose;
      s.LastPose = t.ValidPose;
      out.push_back(s);
    }
  }
  return out;
}

std::vector<vtkRPTrackingLogic::ImageStatistics> vtkRPTrackingLogic::GetImageStatistics() const {
  std::vector<ImageStatistics> out;
  for (const auto& [id, source] : this->Sources) {
    for (const Image& i : source.Streams) {
      ImageStatistics s;
      s.NodeName = i.NodeName;
      s.NodeID = i.NodeID;
      s.Frames = i.Published;
      s.Shown = i.Shown;
      std::copy(i.Dimensions, i.Dimensions + 3, s.Dimensions);
      s.LatencySeconds = i.Latency;
      out.push_back(s);
    }
  }
  return out;
}

rp::PivotResult vtkRPTrackingLogic::CalibratePivot(const std::vector<rp::ToolPose>& poses,
                                                   const std::string& stylusNodeName, double thresholdMm,
                                                   double minSpreadDeg, vtkRPLinearTransformNode** tip) {
  const rp::PivotResult result = rp::PivotCalibrate(poses, thresholdMm, minSpreadDeg);
  vtkRPLinearTransformNode* applied = result.Valid ? this->ApplyPivotCalibration(result, stylusNodeName) : nullptr;
  if (tip) *tip = applied;
  return result;
}

vtkRPLinearTransformNode* vtkRPTrackingLogic::ApplyPivotCalibration(const rp::PivotResult& result,
                                                                    const std::string& stylusNodeName,
                                                                    const std::string& tipNodeName) {
  if (!this->Scene || !result.Valid) return nullptr;
  double m[16];
  rp::TipOffsetMatrix(result.TipOffset, m);
  vtkRPLinearTransformNode* tip = this->SetTransformUnder(tipNodeName, m, stylusNodeName);
  tip->SetAttribute(PivotCalibrationRMSEAttribute(), std::to_string(result.Rmse));
  return tip;
}

rp::PhantomRegistrationResult vtkRPTrackingLogic::RegisterPhantom(const std::string& recordingPath,
                                                                  const std::string& configPath,
                                                                  rp::LandmarkDetectionMethod method,
                                                                  rp::PlusPhantomConfiguration& config,
                                                                  vtkRPLinearTransformNode** applied) {
  if (applied) *applied = nullptr;
  rp::PhantomRegistrationResult result;
  rp::PlusSequence recording;
  try {
    config = rp::PlusPhantomConfiguration::Read(configPath);
    recording = rp::ReadPlusSequence(recordingPath);
  } catch (const std::exception& e) {
    result.Error = e.what();
    return result;
  }
  result = rp::RegisterPhantomFromRecording(recording, config, method);
  vtkRPLinearTransformNode* node = result.Ok ? this->ApplyPhantomRegistration(result, config) : nullptr;
  if (applied) *applied = node;
  return result;
}

vtkRPLinearTransformNode* vtkRPTrackingLogic::ApplyPhantomRegistration(const rp::PhantomRegistrationResult& result,
                                                                       const rp::PlusPhantomConfiguration& config) {
  if (!this->Scene || !result.Ok) return nullptr;
  double m[16];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[4 * r + c] = result.PhantomToReference(r, c);
  vtkRPLinearTransformNode* node = this->SetTransformUnder(config.PhantomFrame + "To" + config.ReferenceFrame, m,
                                                           config.ReferenceFrame + "ToTracker");
  node->SetAttribute(PhantomRegistrationFREAttribute(), std::to_string(result.FRE));
  return node;
}

vtkRPLinearTransformNode* vtkRPTrackingLogic::SetTransformUnder(const std::string& name, const double toParent[16],
                                                                const std::string& parentName) {
  vtkRPLinearTransformNode* node = nullptr;
  for (vtkRPNode* n : this->Scene->GetNodesByName(name))
    if ((node = vtkRPLinearTransformNode::SafeDownCast(n))) break;
  if (!node) {
    vtkNew<vtkRPLinearTransformNode> created;
    created->SetName(name);
    this->Scene->AddNode(created);
    node = created;
  }
  node->SetMatrixTransformToParent(toParent);
  for (vtkRPNode* n : this->Scene->GetNodesByName(parentName))
    if (vtkRPLinearTransformNode::SafeDownCast(n)) {
      node->SetAndObserveTransformNodeID(n->GetID());
      break;
    }
  return node;
}

bool vtkRPTrackingLogic::ReadToolDefinitionFile(const std::string& path, rp::rom::Definition& definition,
                                                std::vector<uint8_t>& rom, std::string& error) {
  try {
    if (std::filesystem::path(path).extension() == ".json") {
      rom = rp::ReadToolDefinition(path).Rom;
      return rp::rom::Read(rom.data(), rom.size(), definition, error);
    }
    definition = rp::rom::ReadFile(path, &rom);  // checksum verified
    return true;
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
}

std::unique_ptr<rp::PolarisSimulator> vtkRPTrackingLogic::StartSimulatedPolaris(
    const rp::PolarisSimulatorOptions& options, const std::vector<rp::ToolDefinition>& tools,
    const std::vector<int>& ports, std::string& error) {
  auto simulator = std::make_unique<rp::PolarisSimulator>(options);
  for (size_t i = 0; i < tools.size(); ++i) simulator->AddTool(tools[i], i < ports.size() ? ports[i] : -1);
  if (!simulator->Start(error)) return nullptr;
  return simulator;
}
