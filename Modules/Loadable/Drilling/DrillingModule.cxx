// The Drilling module: remove bone with a spherical burr at the servo rate (the seed paper's
// "drilling" of section 5). CLI: roboplan drill (Logic/rpDrillCommand.h).
#include <iostream>

#include "rpDrillCommand.h"
#include "rpModule.h"

namespace {

class DrillingModule : public rp::Module {
 public:
  std::string Name() const override { return "Drilling"; }
  std::string Title() const override { return "Drilling"; }
  std::vector<rp::Command> Commands() override {
    return {{"drill", "drill a stroke into a bone with a burr at 1 kHz (removed volume, forces, timings)",
             [](rp::CommandContext& context) { return rp::RunDrillCommand(context.Arguments, std::cout, std::cerr); }}};
  }
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(DrillingModule)
