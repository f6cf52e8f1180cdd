// The Haptics module plugin: touch the patient's tissues at 1 kHz (seed 2.2, 3.2.1). CLI
// `roboplan haptics` (Logic/rpHapticsCommand.cxx), panel qRPHapticsPanel.

#include <vtkNew.h>

#include "rpHapticsCommand.h"
#include "rpModule.h"
#include "vtkRPHapticsLogic.h"

namespace {

class HapticsModule : public rp::Module {
 public:
  std::string Name() const override { return "Haptics"; }
  std::string Title() const override { return "Haptics"; }
  void Setup(vtkRPScene* scene) override { this->LogicObject->SetScene(scene); }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    return {{"haptics", "touch the haptic models at 1 kHz with a simulated device (timing, forces, clamped tissues)",
             [](rp::CommandContext& c) { return rp::RunHapticsCommand(c.Arguments, c.Scene, *c.Out, *c.Err); }}};
  }

 private:
  vtkNew<vtkRPHapticsLogic> LogicObject;
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(HapticsModule)
