// The Workflow module: the seed's whole workflow end to end (`roboplan demo`).
#include <iostream>

#include <nlohmann/json.hpp>

#include "rpArgParser.h"
#include "rpDemo.h"
#include "rpModule.h"

namespace {

int RunDemoCommand(rp::CommandContext& context) {
  rp::ArgParser parser("demo",
                       "Run the seed's whole workflow on the built-in knee phantom (or on your CT with --data) and "
                       "write the scene, meshes, segmentation, fiducials, transforms, logs and report.html to the "
                       "output folder. Exits 1 if a stage fails (everything done so far is kept).");
  parser.Option("out", "dir", "output folder", "roboplan-demo")
      .Option("data", "dicom folder", "run on a CT series instead of the phantom")
      .Option("truth", "labelmap", "with --data: the CT's bones as a labelmap (any grid) to score each bone against")
      .Option("truth-names", "label table", "names of --truth's label values (Slicer colour table or ITK-SNAP)")
      .Option("size", "small|demo|full", "phantom size", "demo")
      .Option("haptic-seconds", "s", "length of the haptic exploration", "4")
      .Flag("no-screenshots", "skip the 4-up pictures (no display needed)");
  if (!parser.Parse(context.Arguments)) {
    if (parser.HelpRequested()) {
      std::cout << parser.Usage();
      return 0;
    }
    std::cerr << "roboplan demo: " << parser.Error() << "\n\n" << parser.Usage();
    return 2;
  }
  rp::DemoOptions options;
  options.OutputDirectory = parser.Get("out");
  options.DicomData = parser.Get("data");
  options.TruthLabels = parser.Get("truth");
  options.TruthNames = parser.Get("truth-names");
  if ((!options.TruthLabels.empty() || !options.TruthNames.empty()) && options.DicomData.empty()) {
    std::cerr << "roboplan demo: --truth and --truth-names go with --data (the phantom has its own truth)\n";
    return 2;
  }
  options.PhantomSize = parser.Get("size");
  try {
    options.HapticSeconds = parser.GetDouble("haptic-seconds");
  } catch (const std::exception& e) {
    std::cerr << "roboplan demo: " << e.what() << "\n";
    return 2;
  }
  options.Screenshots = !parser.Has("no-screenshots");
  options.Quiet = parser.Json();
  const rp::DemoResult result = rp::RunDemo(options);
  if (parser.Json()) {
    nlohmann::json doc = {{"ok", result.Ok},         {"error", result.Error},
                          {"report", result.ReportPath}, {"scene", result.ScenePath},
                          {"figuresFailed", result.FiguresFailed}, {"seconds", result.Seconds}};
    std::cout << doc.dump(2) << "\n";
  } else {
    std::cerr << (result.Ok ? "demo finished" : "demo FAILED: " + result.Error) << " in " << int(result.Seconds + 0.5)
              << " s\n  report: " << result.ReportPath << "\n  scene:  " << result.ScenePath << "\n";
    if (result.FiguresFailed > 0) std::cerr << "  " << result.FiguresFailed << " figure(s) missed their target\n";
  }
  return result.Ok ? 0 : 1;
}

class WorkflowModule : public rp::Module {
 public:
  std::string Name() const override { return "Workflow"; }
  std::string Title() const override { return "Workflow (main job)"; }
  std::vector<rp::Command> Commands() override {
    return {{"demo", "run the seed's whole workflow on the knee phantom and write report.html", RunDemoCommand}};
  }
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(WorkflowModule)
