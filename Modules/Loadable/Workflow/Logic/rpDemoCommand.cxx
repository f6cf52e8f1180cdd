#include "rpDemoCommand.h"

#include <exception>

#include <nlohmann/json.hpp>

#include "rpArgParser.h"
#include "rpDemo.h"

namespace rp {

int RunDemoCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  ArgParser parser("demo",
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
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  DemoOptions options;
  options.OutputDirectory = parser.Get("out");
  options.DicomData = parser.Get("data");
  options.TruthLabels = parser.Get("truth");
  options.TruthNames = parser.Get("truth-names");
  if ((!options.TruthLabels.empty() || !options.TruthNames.empty()) && options.DicomData.empty()) {
    err << "roboplan demo: --truth and --truth-names go with --data (the phantom has its own truth)\n";
    return 2;
  }
  options.PhantomSize = parser.Get("size");
  try {
    options.HapticSeconds = parser.GetDouble("haptic-seconds");
  } catch (const std::exception& e) {
    err << "roboplan demo: " << e.what() << "\n";
    return 2;
  }
  options.Screenshots = !parser.Has("no-screenshots");
  options.Quiet = parser.Json();
  const DemoResult result = RunDemo(options);
  if (parser.Json()) {
    nlohmann::json doc = {{"ok", result.Ok},         {"error", result.Error},
                          {"report", result.ReportPath}, {"scene", result.ScenePath}, {"slicerBundle", result.BundlePath},
                          {"figuresFailed", result.FiguresFailed}, {"seconds", result.Seconds}};
    out << doc.dump(2) << "\n";
  } else {
    err << (result.Ok ? "demo finished" : "demo FAILED: " + result.Error) << " in " << int(result.Seconds + 0.5)
        << " s\n  report: " << result.ReportPath << "\n  scene:  " << result.ScenePath
        << "\n  Slicer: " << result.BundlePath << "\n";
    if (result.FiguresFailed > 0) err << "  " << result.FiguresFailed << " figure(s) missed their target\n";
  }
  return result.Ok ? 0 : 1;
}

}  // namespace rp
