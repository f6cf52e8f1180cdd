// Tracking module plugin: NDI Polaris tool poses into the scene through a direct serial link or
// OpenIGTLink. CLI: `roboplan track`, `roboplan pivot`, `roboplan polaris-sim`, `roboplan phantom-registration`.

#include <vtkSmartPointer.h>

#include "rpModule.h"
#include "rpDeviceCommands.h"
#include "rpPhantomRegistrationCommand.h"
#include "rpTrackingCommands.h"
#include "vtkRPTrackingLogic.h"

namespace {
class TrackingModule : public rp::Module {
 public:
  std::string Name() const override { return "Tracking"; }
  std::string Title() const override { return "Tracking"; }
  void Setup(vtkRPScene* scene) override {
    this->LogicObject = vtkSmartPointer<vtkRPTrackingLogic>::New();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    return {
        {"track", "track tools from a pose source (--serial, --igtl, --replay, --simulate); pose, frame counts, rate, latency per tool",
         [](rp::CommandContext& c) { return rp::RunTrackCommand(c.Arguments, c.Scene, *c.Out, *c.Err); }},
        {"pivot", "pivot calibration (StylusTipToStylus, RMSE) from a tracking recording",
         [](rp::CommandContext& c) { return rp::RunPivotCommand(c.Arguments, *c.Out, *c.Err); }},
        {"tool-info", "an NDI tool definition (.rom) or tool .json: markers, normals, part number, checksum (--json, --write)",
         [](rp::CommandContext& c) { return rp::RunToolInfoCommand(c.Arguments, *c.Out, *c.Err); }},
        {"polaris-sim", "a simulated NDI Polaris on a pseudo-terminal (prints the port to open)",
         [](rp::CommandContext& c) { return rp::RunPolarisSimCommand(c.Arguments, *c.Out, *c.Err); }},
        {"phantom-registration",
         "PLUS's phantom registration (fCal, landmark detection) from a PLUS recording and configuration: "
         "PhantomToReference, FRE, predicted TRE",
         [](rp::CommandContext& c) { return rp::RunPhantomRegistrationCommand(c.Arguments, *c.Out, *c.Err); }},
    };
  }

 private:
  vtkSmartPointer<vtkRPTrackingLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(TrackingModule)
