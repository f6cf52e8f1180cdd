#include "rpDemo.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpDemoStages.h"
#include "rpReport.h"
#include "rpMrmlScene.h"
#include "rpSceneIO.h"
#include "rpStageRunner.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace rp {

DemoResult RunDemo(const DemoOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  DemoResult result;
  std::error_code ec;
  fs::create_directories(options.OutputDirectory, ec);
  if (ec) {
    result.Error = "cannot create output folder '" + options.OutputDirectory + "': " + ec.message();
    return result;
  }
  Report report(options.DicomData.empty() ? "RoboPlan demo: the built-in knee phantom"
                                          : "RoboPlan demo: " + options.DicomData);
  DemoState state;
  state.Options = options;
  state.Output = fs::absolute(options.OutputDirectory).string();
  state.Report = &report;
  state.Scene = vtkSmartPointer<vtkRPScene>::New();

  const std::vector<DemoStage> stages = DemoStages();
  StageRunner runner(report, static_cast<int>(stages.size()), options.Quiet);
  state.Runner = &runner;
  for (const DemoStage& stage : stages) {
    runner.Run(stage.Name, [&] { stage.Run(state); });
  }
  // The scene and the report are written whatever happened: everything done so far is kept.
  std::string error;
  result.ScenePath = (fs::path(state.Output) / "scene.rpscene").string();
  if (!SaveScene(state.Scene, result.ScenePath, error)) {
    report.AddNote("Saving the scene failed: " + error);
    if (result.Error.empty()) result.Error = "saving the scene failed: " + error;
  }
  // The same plan as 3D Slicer's bundle: opens in Slicer in one step.
  result.BundlePath = (fs::path(state.Output) / "plan.mrb").string();
  SceneTransferReport bundle;
  if (!WriteMrmlBundle(state.Scene, result.BundlePath, bundle) || !bundle.FirstProblem().empty()) {
    const std::string why = bundle.Ok ? bundle.FirstProblem() : bundle.Error;
    report.AddNote("Saving the Slicer bundle failed: " + why);
    if (result.Error.empty()) result.Error = "saving the Slicer bundle failed: " + why;
  }
  result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.AddNote("Total time: " + std::to_string(static_cast<int>(result.Seconds + 0.5)) + " s on " +
                 std::to_string(std::thread::hardware_concurrency()) + " cores.");
  result.ReportPath = (fs::path(state.Output) / "report.html").string();
  if (!report.Write(result.ReportPath, error) && result.Error.empty()) result.Error = error;
  result.FiguresFailed = report.CountFailed();
  if (runner.Failed()) result.Error = runner.FailureMessage();
  result.Ok = !runner.Failed() && result.Error.empty();
  return result;
}

}  // namespace rp
