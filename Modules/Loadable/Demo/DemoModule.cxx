// The Workflow module: the seed's whole workflow end to end. CLI `roboplan demo`
// (Logic/rpDemoCommand.cxx).
#include <iostream>

#include "rpDemoCommand.h"
#include "rpModule.h"

namespace {

class WorkflowModule : public rp::Module {
 public:
  std::string Name() const override { return "Workflow"; }
  std::string Title() const override { return "Workflow (main job)"; }
  std::vector<rp::Command> Commands() override {
    return {{"demo", "run the seed's whole workflow on the knee phantom and write report.html",
             [](rp::CommandContext& c) { return rp::RunDemoCommand(c.Arguments, std::cout, std::cerr); }}};
  }
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(WorkflowModule)
