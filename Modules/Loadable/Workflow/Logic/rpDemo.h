#pragma once
// The main job, `roboplan demo` (seed sections 3.3 and 4): on the built-in knee phantom (or a
// user's CT with --data), in one run: write and load the CT and MR DICOM series, register
// CT↔MR, segment and mesh bones and soft tissues, pivot-calibrate the stylus on a simulated
// Polaris, register patient to image, navigate a scripted tool path with re-slicing, and
// explore the knee haptically at 1 kHz. Everything goes to an output folder with report.html.
#include <string>

namespace rp {

struct DemoOptions {
  std::string OutputDirectory = "roboplan-demo";
  std::string DicomData;          // a user's CT series folder instead of the phantom ("" = phantom)
  std::string TruthLabels;        // with DicomData: a labelmap of its bones to score against ("" = none)
  std::string TruthNames;         // optional label table naming TruthLabels' values (Slicer .ctbl / ITK-SNAP)
  std::string PhantomSize = "demo";  // small | demo (default) | full
  double HapticSeconds = 4.0;     // haptic exploration length
  bool Screenshots = true;        // render 4-up pictures (needs a display or Xvfb)
  bool Quiet = false;             // no progress lines (--json)
};

struct DemoResult {
  bool Ok = false;
  std::string Error;         // first failing stage and why
  std::string ReportPath;
  std::string ScenePath;
  std::string BundlePath;  // plan.mrb: the scene as 3D Slicer's bundle
  int FiguresFailed = 0;
  double Seconds = 0;
};

DemoResult RunDemo(const DemoOptions& options);

}  // namespace rp
