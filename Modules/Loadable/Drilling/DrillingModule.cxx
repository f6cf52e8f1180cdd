// The Drilling module: remove bone with a spherical burr at the servo rate (the seed paper's
// "drilling" of section 5). Logic: vtkRPDrillingLogic; panel: qRPDrillingPanel; CLI: roboplan drill.

#include <vtkNew.h>

#include "rpDrillCommand.h"
#include "rpImagingReaders.h"
#include "rpModule.h"
#include "vtkRPDrillingLogic.h"
#ifdef ROBOPLAN_BUILD_GUI
#include "qRPDrillingPanel.h"
#endif

namespace {

class DrillingModule : public rp::Module {
 public:
  std::string Name() const override { return "Drilling"; }
  std::string Title() const override { return "Drilling"; }
  // What this module registers: the imaging readers (a DICOM SEG or a DICOM CT through the loader).
  void Setup(vtkRPScene* scene) override {
    rp::RegisterImagingReaders();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  QWidget* CreatePanel(QWidget* parent) override {
#ifdef ROBOPLAN_BUILD_GUI
    return new qRPDrillingPanel(this->LogicObject, parent);
#else
    (void)parent;
    return nullptr;
#endif
  }
  std::vector<rp::Command> Commands() override {
    return {{"drill", "drill a stroke into a bone with a burr at 1 kHz (removed volume, forces, timings)",
             [](rp::CommandContext& c) { return rp::RunDrillCommand(c.Arguments, c.Scene, *c.Out, *c.Err); }}};
  }

 private:
  vtkNew<vtkRPDrillingLogic> LogicObject;
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(DrillingModule)
