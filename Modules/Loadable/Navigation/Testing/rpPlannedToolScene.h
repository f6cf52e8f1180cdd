#pragma once
// A scene the navigation tests share: a planned trajectory from `entry` to `target`, a tool tip
// (a linear transform, the tool pointing along its −z) and the navigation logic following it
// against that plan.
#include <vtkNew.h>

#include "vtkRPLinearTransformNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"
#include "vtkRPTrajectoryNode.h"

namespace rptest {

struct PlannedToolScene {
  vtkNew<vtkRPScene> Scene;
  vtkNew<vtkRPTrajectoryNode> Trajectory;
  vtkNew<vtkRPLinearTransformNode> Tip;
  vtkNew<vtkRPNavigationLogic> Logic;

  PlannedToolScene(const double entry[3], const double target[3]) {
    this->Trajectory->SetEntryAndTarget(entry, target);
    this->Scene->AddNode(this->Trajectory);
    this->Scene->AddNode(this->Tip);
    this->Logic->SetScene(this->Scene);
    this->Logic->SetToolNodeID(this->Tip->GetID());
    this->Logic->SetTrajectoryNodeID(this->Trajectory->GetID());
  }
  /// Moves the tip (row-major TipToRAS): the logic reads it out on the move.
  const rp::GuidanceReadout& Place(const double tipToRAS[16]) {
    this->Tip->SetMatrixTransformToParent(tipToRAS);
    return this->Logic->GetLastReadout();
  }
};

}  // namespace rptest
