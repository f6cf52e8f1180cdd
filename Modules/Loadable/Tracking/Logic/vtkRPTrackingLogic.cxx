#include "vtkRPTrackingLogic.h"

#include <algorithm>

#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>

#include "rpTransformNames.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"

vtkStandardNewMacro(vtkRPTrackingLogic);

vtkRPTrackingLogic::vtkRPTrackingLogic() = default;
vtkRPTrackingLogic::~vtkRPTrackingLogic() = default;

void vtkRPTrackingLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Sources: " << this->Sources.size() << "\n"
     << indent << "StaleTimeout: " << this->StaleTimeout << "\n"
     << indent << "AutoCreateNodes: " << this->AutoCreateNodes << "\n";
}

void vtkRPTrackingLogic::SetScene(vtkRPScene* scene) {
  this->Scene = scene;
  for (auto& [id, source] : this->Sources)
    for (Tool& t : source.Tools) t.NodeID.clear();
  this->DerivedNodeIDs.clear();
}

int vtkRPTrackingLogic::AddPoseSource(const rp::ToolPoseTable* table) {
  const int id = this->NextSourceId++;
  this->Sources[id].Table = table;
  return id;
}

void vtkRPTrackingLogic::RemovePoseSource(int sourceId) { this->Sources.erase(sourceId); }

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
}  // namespace

int vtkRPTrackingLogic::UpdateNodes(double now) {
  if (!this->Scene) return 0;
  int modified = 0;
  this->Scene->StartBatchProcess();
  const Tool* reference = nullptr;
  std::vector<const Tool*> all, changed;
  for (auto& [id, source] : this->Sources) {
    const int count = source.Table->Count();
    if (static_cast<int>(source.Tools.size()) < count) {
      const size_t old = source.Tools.size();
      source.Tools.resize(static_cast<size_t>(count));
      for (size_t i = old; i < source.Tools.size(); ++i)
        source.Tools[i].NodeName = source.Table->Name(static_cast<int>(i));
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
        tool.Latency = now - sample.Pose.ReceiveTime;
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
      const auto& sample = source.Reader.Last(static_cast<int>(slot));
      ToolStatistics s;
      s.NodeName = t.NodeName;
      s.NodeID = t.NodeID;
      s.Status = t.Status;
      s.Received = sample.Received;
      s.Dropped = sample.Dropped;
      s.RateHz = t.RateHz;
      s.LatencySeconds = t.Latency;
      s.ErrorRMS = t.ErrorRMS;
      out.push_back(s);
    }
  }
  return out;
}

vtkRPLinearTransformNode* vtkRPTrackingLogic::ApplyPivotCalibration(const rp::PivotResult& result,
                                                                    const std::string& stylusNodeName,
                                                                    const std::string& tipNodeName) {
  if (!this->Scene || !result.Valid) return nullptr;
  vtkRPLinearTransformNode* tip = nullptr;
  for (vtkRPNode* n : this->Scene->GetNodesByName(tipNodeName))
    if ((tip = vtkRPLinearTransformNode::SafeDownCast(n))) break;
  if (!tip) {
    vtkNew<vtkRPLinearTransformNode> created;
    created->SetName(tipNodeName);
    this->Scene->AddNode(created);
    tip = created;
  }
  double m[16];
  rp::TipOffsetMatrix(result.TipOffset, m);
  tip->SetMatrixTransformToParent(m);
  for (vtkRPNode* n : this->Scene->GetNodesByName(stylusNodeName)) {
    if (vtkRPLinearTransformNode::SafeDownCast(n)) {
      tip->SetAndObserveTransformNodeID(n->GetID());
      break;
    }
  }
  tip->SetAttribute("PivotRMSE", std::to_string(result.Rmse));
  return tip;
}
