// Depends on TestGood: the manager must set TestGood up first.
#include "rpModule.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"

#include <vtkNew.h>

namespace {
class TestDependentModule : public rp::Module {
 public:
  std::string Name() const override { return "TestDependent"; }
  std::vector<std::string> Dependencies() const override { return {"TestGood"}; }
  void Setup(vtkRPScene* scene) override {
    // Records the order: TestGood's Setup ran before ours if its marker node is there.
    if (!scene) return;
    vtkNew<vtkRPLinearTransformNode> marker;
    marker->SetName(scene->GetFirstNodeByName("TestGood") ? "TestDependent after TestGood" : "TestDependent first");
    scene->AddNode(marker);
  }
  std::vector<rp::Command> Commands() override {
    return {{"test-dependent", "returns 45", [](rp::CommandContext&) { return 45; }}};
  }
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(TestDependentModule)
