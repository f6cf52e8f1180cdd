// The TemplateKey module's plugin entry: it only names the module, makes its logic and lists its
// CLI commands (the work is in Logic/, the panel in Widgets/ when it has one).

#include <vtkSmartPointer.h>

#include "rpModule.h"
#include "rpTemplateKeyCommand.h"
#include "vtkRPTemplateKeyLogic.h"

namespace {
class TemplateKeyModule : public rp::Module {
 public:
  std::string Name() const override { return "TemplateKey"; }
  std::string Title() const override { return "TemplateKey"; }
  void Setup(vtkRPScene* scene) override {
    this->LogicObject = vtkSmartPointer<vtkRPTemplateKeyLogic>::New();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    return {{"templatekey-summary", "load files into a scene and count its nodes by class",
             [](rp::CommandContext& c) { return rp::RunTemplateKeySummaryCommand(c.Arguments, *c.Out, *c.Err); }}};
  }

 private:
  vtkSmartPointer<vtkRPTemplateKeyLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(TemplateKeyModule)
