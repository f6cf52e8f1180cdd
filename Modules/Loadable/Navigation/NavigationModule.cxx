// Navigation module plugin (seed 3.3): the tip-to-surface distance of a tool to chosen models,
// with a warning under a threshold (the logic writes Navigation.* attributes onto the tool node);
// `roboplan score`, an execution scored against its plan (issue 38).
#include <vtkSmartPointer.h>

#include "rpModule.h"
#include "rpScoreCommand.h"
#include "vtkRPNavigationLogic.h"

namespace {
class NavigationModule : public rp::Module {
 public:
  std::string Name() const override { return "Navigation"; }
  std::string Title() const override { return "Navigation"; }
  void Setup(vtkRPScene* scene) override {
    this->LogicObject = vtkSmartPointer<vtkRPNavigationLogic>::New();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    return {{"score", "an execution (drilling recording, PLUS sequence or CSV of tip points) scored against its plan",
             [](rp::CommandContext& context) { return rp::RunScoreCommand(context.Arguments, *context.Out, *context.Err); }}};
  }

 private:
  vtkSmartPointer<vtkRPNavigationLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(NavigationModule)
