// The Planning module: plans as scene nodes (trajectories, screws, cut planes, structures at
// risk), checked against the CT before anything is cut. Logic: vtkRPPlanningLogic; panel:
// qRPPlanningPanel; CLI: roboplan plan.
#include <vtkSmartPointer.h>

#include "rpImagingReaders.h"
#include "rpModule.h"
#include "rpPlanCommand.h"
#include "vtkRPPlanningLogic.h"
#ifdef ROBOPLAN_BUILD_GUI
#include "qRPPlanningPanel.h"
#endif

namespace {
class PlanningModule : public rp::Module {
 public:
  std::string Name() const override { return "Planning"; }
  std::string Title() const override { return "Planning"; }
  // What this module registers: the imaging readers (`plan --ct` reads DICOM through the loader).
  void Setup(vtkRPScene* scene) override {
    rp::RegisterImagingReaders();
    this->LogicObject = vtkSmartPointer<vtkRPPlanningLogic>::New();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  QWidget* CreatePanel(QWidget* parent) override {
#ifdef ROBOPLAN_BUILD_GUI
    return new qRPPlanningPanel(this->LogicObject, parent);
#else
    (void)parent;
    return nullptr;
#endif
  }
  std::vector<rp::Command> Commands() override {
    return {{"plan", "plan trajectories, screws and cut planes; check them against the CT and the structures at risk; "
                     "propose an entry",
             [](rp::CommandContext& c) { return rp::RunPlanCommand(c.Arguments, *c.Out, *c.Err); }}};
  }

 private:
  vtkSmartPointer<vtkRPPlanningLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(PlanningModule)
