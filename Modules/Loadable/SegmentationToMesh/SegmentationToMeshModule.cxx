// SegmentationToMesh module plugin: logic vtkRPSegmentationToMeshLogic, panel
// qRPSegmentationToMeshPanel and `roboplan mesh` (Logic/rpMeshCommand.cxx) all segment and mesh
// through the logic.

#include <vtkNew.h>

#include "rpMeshCommand.h"
#include "rpImagingReaders.h"
#include "rpModule.h"
#include "vtkRPSegmentationToMeshLogic.h"
#ifdef ROBOPLAN_BUILD_GUI
#include <QScrollArea>

#include "qRPSegmentationToMeshPanel.h"
#endif

namespace {

class SegmentationToMeshModule : public rp::Module {
 public:
  std::string Name() const override { return "SegmentationToMesh"; }
  std::string Title() const override { return "Segmentation to Mesh"; }
  // What this module registers: the imaging readers (it reads DICOM through the loader).
  void Setup(vtkRPScene* scene) override {
    rp::RegisterImagingReaders();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  QWidget* CreatePanel(QWidget* parent) override {
#ifdef ROBOPLAN_BUILD_GUI
    if (!this->LogicObject->GetScene()) return nullptr;
    // The panel is taller than a module page on a laptop screen: let it scroll.
    auto* scroll = new QScrollArea(parent);
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    scroll->setWidget(new qRPSegmentationToMeshPanel(this->LogicObject));
    return scroll;
#else
    (void)parent;
    return nullptr;
#endif
  }
  std::vector<rp::Command> Commands() override {
    return {{"mesh", "segment a CT/MR (or take a .seg.nrrd) and write one closed surface per tissue",
             [](rp::CommandContext& c) { return rp::RunMeshCommand(c.Arguments, c.Scene, *c.Out, *c.Err); }}};
  }

 private:
  vtkNew<vtkRPSegmentationToMeshLogic> LogicObject;
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(SegmentationToMeshModule)
