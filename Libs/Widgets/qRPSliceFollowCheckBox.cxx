#include "qRPSliceFollowCheckBox.h"

#include <QSignalBlocker>

#include "vtkRPSliceNode.h"

qRPSliceFollowCheckBox::qRPSliceFollowCheckBox(const QString& text, QWidget* parent) : QCheckBox(text, parent) {
  this->setToolTip("Re-slice the views at this tool's tip as it moves (changes the scene's slice nodes)");
  connect(this, &QCheckBox::toggled, this, &qRPSliceFollowCheckBox::OnToggled);
}

void qRPSliceFollowCheckBox::SetScene(vtkRPScene* scene) { this->Scene = scene; }

void qRPSliceFollowCheckBox::SetFollowNodeID(const std::string& id) {
  if (id == this->NodeID) return;
  // A new tool while ticked: the slices move over to it (if they followed the old one).
  const bool wasFollowing = this->isChecked() && this->IsFollowing();
  this->NodeID = id;
  if (wasFollowing || (this->isChecked() && this->Pending)) {
    this->Pending = true;
    this->Refresh();
  }
}

bool qRPSliceFollowCheckBox::IsFollowing() const {
  const auto slices = vtkRPSliceNode::GetSliceNodes(this->Scene);
  if (this->NodeID.empty() || slices.empty()) return false;
  for (vtkRPSliceNode* slice : slices) {
    if (slice->GetFollowNodeID() != this->NodeID) return false;
  }
  return true;
}

void qRPSliceFollowCheckBox::OnToggled(bool on) {
  if (!on && this->IsFollowing()) vtkRPSliceNode::SetAllSlicesFollow(this->Scene, "");
  this->Pending = on;
  this->Refresh();
}

void qRPSliceFollowCheckBox::Refresh() {
  if (!this->isChecked() || !this->Scene) return;
  const bool exists = !this->NodeID.empty() && this->Scene->GetNodeByID(this->NodeID) != nullptr;
  if (this->Pending) {
    if (exists && vtkRPSliceNode::SetAllSlicesFollow(this->Scene, this->NodeID)) this->Pending = false;
    return;
  }
  if (!this->IsFollowing()) {
    const QSignalBlocker block(this);
    this->setChecked(false);
  }
}
