// The Demo module: the seed's whole workflow end to end. CLI `roboplan demo`
// (Logic/rpDemoCommand.cxx). The only module that depends on other modules: it drives their logic.

#include "rpDemoCommand.h"
#include "rpImagingReaders.h"
#include "rpModule.h"

namespace {

class DemoModule : public rp::Module {
 public:
  std::string Name() const override { return "Demo"; }
  std::string Title() const override { return "Demo (main job)"; }
  std::vector<std::string> Dependencies() const override {
    return {"Drilling", "Haptics", "LandmarkRegistration", "Navigation", "SegmentationToMesh", "Tracking"};
  }
  // What this module registers: the imaging readers (--truth, --data through the loader).
  void Setup(vtkRPScene*) override { rp::RegisterImagingReaders(); }
  std::vector<rp::Command> Commands() override {
    return {{"demo", "run the seed's whole workflow on the knee phantom and write report.html",
             [](rp::CommandContext& c) { return rp::RunDemoCommand(c.Arguments, *c.Out, *c.Err); }}};
  }
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(DemoModule)
