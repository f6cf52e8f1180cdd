// Volumes module plugin: DICOM series, NRRD/NIfTI, the knee phantom and CT-MR registration.
// CLI: `roboplan dicom`, `roboplan convert`, `roboplan phantom`, `roboplan register-volumes`.

#include <vtkSmartPointer.h>

#include "rpImagingReaders.h"
#include "rpModule.h"
#include "rpVolumesCommands.h"
#include "vtkRPVolumesLogic.h"

namespace {
class VolumesModule : public rp::Module {
 public:
  std::string Name() const override { return "Volumes"; }
  std::string Title() const override { return "Volumes"; }
  // What this module registers: the imaging readers (it reads DICOM through the loader).
  void Setup(vtkRPScene* scene) override {
    rp::RegisterImagingReaders();
    this->LogicObject = vtkSmartPointer<vtkRPVolumesLogic>::New();
    this->LogicObject->SetScene(scene);
  }
  vtkObject* Logic() override { return this->LogicObject; }
  std::vector<rp::Command> Commands() override {
    auto bind = [](int (*run)(const std::vector<std::string>&, std::ostream&, std::ostream&)) {
      return [run](rp::CommandContext& context) { return run(context.Arguments, *context.Out, *context.Err); };
    };
    return {{"dicom", "list the DICOM image series in a folder or DICOMDIR", bind(rp::RunDicomCommand)},
            {"convert", "convert volumes between DICOM series, NRRD, NIfTI and MetaImage", bind(rp::RunConvertCommand)},
            {"phantom", "write the built-in knee phantom (CT, MR, labels, true transform)", bind(rp::RunPhantomCommand)},
            {"register-volumes", "rigid CT-MR registration by mutual information into a transform file",
             bind(rp::RunRegisterVolumesCommand)},
            {"compare-labels", "score a segmentation against a truth labelmap (Dice, surface distance)",
             bind(rp::RunCompareLabelsCommand)}};
  }

 private:
  vtkSmartPointer<vtkRPVolumesLogic> LogicObject;
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(VolumesModule)
