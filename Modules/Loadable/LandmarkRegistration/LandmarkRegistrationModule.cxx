// LandmarkRegistration module plugin: paired-point registration of two fiducial lists into a
// linear transform node, with FRE, accept/reject, predicted TRE (CLI `roboplan register`).

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpModule.h"
#include "rpRegisterCommand.h"
#include "vtkRPLandmarkRegistrationLogic.h"

namespace {
class LandmarkRegistrationModule : public rp::Module {
 public:
  std::string Name() const override { return "LandmarkRegistration"; }
  std::string Title() const override { return "Landmark Registration"; }
  void Setup(vtkRPScene*) override { this->LogicObject = vtkSmartPointer<vtkRPLandmarkRegistrationLogic>::New(); }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    return {{"register",
             "paired-point registration of two fiducial files into a transform file, with FRE, "
             "accept/reject and predicted TRE",
             [](rp::CommandContext& context) { return rp::RunRegisterCommand(context.Arguments, *context.Out, *context.Err); }}};
  }

 private:
  vtkSmartPointer<vtkRPLandmarkRegistrationLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(LandmarkRegistrationModule)
