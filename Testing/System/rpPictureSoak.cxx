// The demo's pictures, one after the other in one process, as `roboplan demo` draws them: 4-up
// views of the CT with the bone models (the viewer's offscreen rendering), the bones from the front
// and the side, a line chart, a bar chart and a histogram (VTK's chart classes), then 30 small
// windows back to back, each in its own offscreen window made and dropped in turn. That is the pattern that made the demo abort in a third
// of its runs under `xvfb-run -a` (rpXDisplay.h): a window closing the process's last X connection
// resets the server, and the next window's connection, made a moment later, was refused.
// rpPictureSoakTest.sh runs this 20 times under `xvfb-run -a` and 5 times without DISPLAY.
//
//   rpPictureSoak <output folder>   exit 0 when every picture was written, 1 naming the first that
//                                   was not; an abort (SIGABRT) is what the soak looks for.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "rpBenchmarkChart.h"
#include "rpWindowPicture.h"
#include "rpDemoStages.h"
#include "rpImageVolume.h"
#include "rpKneePhantom.h"
#include "rpReport.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

namespace fs = std::filesystem;

namespace {

bool Fail(const std::string& what, const std::string& why) {
  std::fprintf(stderr, "rpPictureSoak: %s not drawn: %s\n", what.c_str(), why.c_str());
  return false;
}

// Small windows made, drawn and dropped back to back (as the charts of a report are, and the
// benchmarks' GL probe): with a connection per window each one would meet the server still
// resetting from the last one's departure (the race a few milliseconds of work hides on a loaded
// machine, not on an idle one).
bool DrawSmallWindows(const std::string& folder, int count) {
  for (int i = 0; i < count; ++i) {
    vtkNew<vtkRenderWindow> window;
    vtkNew<vtkRenderer> renderer;
    renderer->SetBackground(0.2, 0.4, 0.6);
    window->AddRenderer(renderer);
    window->SetSize(32, 32);
    std::string error;
    if (!rp::bench::WriteWindowPNG(window, folder + "/small.png", error)) return Fail("small window", error);
  }
  return true;
}

bool DrawEverything(rp::DemoState& state) {
  std::string error;
  const double joint[3] = {0, 0, 0}, shaft[3] = {0, 0, -30};
  if (!rp::DemoScreenshot(state, joint, "", "views-joint.png", error)) return Fail("4-up views (joint)", error);
  if (!rp::DemoBoneViews(state, state.BoneModelIDs, "bones.png", error)) return Fail("bone views", error);
  if (!rp::DemoScreenshot(state, shaft, "", "views-shaft.png", error)) return Fail("4-up views (shaft)", error);
  rp::bench::Series line{"ours", {1, 2, 3, 4}, {0.4, 0.3, 0.25, 0.2}};
  rp::bench::Series other{"VTK", {1, 2, 3, 4}, {0.5, 0.45, 0.4, 0.38}};
  rp::bench::ChartOptions options;
  options.Title = "soak";
  const std::string out = state.Output + "/";
  if (!rp::bench::WriteChartPNG(out + "line.png", {line, other}, options, error)) return Fail("line chart", error);
  if (!rp::bench::WriteBarChartPNG(out + "bars.png", {"a", "b", "c", "d"}, {line, other}, options, error))
    return Fail("bar chart", error);
  if (!rp::bench::WriteHistogramPNG(out + "histogram.png", line.X, line.Y, options, error))
    return Fail("histogram", error);
  return DrawSmallWindows(state.Output, 30);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rpPictureSoak <output folder>\n");
    return 2;
  }
  rp::KneePhantomOptions phantomOptions;
  phantomOptions.Size = rp::KneePhantomSize::Small;
  phantomOptions.GenerateMR = false;
  phantomOptions.GenerateLabels = false;
  std::string error;
  auto phantom = std::make_shared<rp::KneePhantom>();
  if (!rp::GenerateKneePhantom(phantomOptions, *phantom, error)) {
    std::fprintf(stderr, "rpPictureSoak: no phantom: %s\n", error.c_str());
    return 1;
  }
  rp::Report report("picture soak");
  rp::DemoState state;
  state.Options.Screenshots = true;
  state.Output = fs::absolute(argv[1]).string();
  fs::create_directories(state.Output);
  state.Report = &report;
  state.Scene = vtkSmartPointer<vtkRPScene>::New();
  state.Phantom = phantom;
  vtkNew<vtkRPScalarVolumeNode> ct;
  ct->SetName("CT");
  rp::CopyToNode(phantom->CT, ct.GetPointer());
  state.Scene->AddNode(ct);
  state.CT = ct;
  phantom->Model->KneeAxes(state.KneeLateral.data(), state.KneeAnterior.data());
  state.KneeAxesKnown = true;
  for (const rp::KneeBone& bone : rp::KneeBones()) {
    vtkNew<vtkRPModelNode> model;
    model->SetName(bone.Name);
    model->SetPolyData(phantom->Model->Surface(bone.Surface));
    model->SetColor(bone.Color[0], bone.Color[1], bone.Color[2]);
    state.Scene->AddNode(model);
    state.BoneModelIDs.push_back(model->GetID());
  }
  return DrawEverything(state) ? 0 : 1;
}
