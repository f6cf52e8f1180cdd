// A minimal module for the loader tests: it registers a command and counts its setup.
#include "rpModule.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"

#include <vtkNew.h>

namespace {
class TestGoodModule : public rp::Module {
 public:
  std::string Name() const override { return "TestGood"; }
  std::string Title() const override { return "Test module (good)"; }
  void Setup(vtkRPScene* scene) override {
    vtkNew<vtkRPLinearTransformNode> marker;
    marker->SetName("TestGood");
    if (scene) scene->AddNode(marker);
  }
  std::vector<rp::Command> Commands() override {
    return {{"test-good", "returns 42", [](rp::CommandContext& c) { return static_cast<int>(c.Arguments.size()) + 42; }}};
  }
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(TestGoodModule)
