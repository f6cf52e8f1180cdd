#pragma once
// Renders views at the display rate, only the views that changed (View::NeedsRender). A view that
// keeps changing tick after tick (a tracked or haptic tool moving, the slices following it) is
// drawn with the interactive level of detail (View::SetInteractive: display meshes decimated to a
// budget); one tick after it stops changing it is drawn once more at full detail. This is VTK's
// interactive/still update rate, coalesced to the display: however many poses arrive between two
// ticks, each view renders at most once per tick. The Qt main window and rpViewerBenchmark use it.
#include <functional>
#include <vector>

namespace rp {

class View;

class RenderScheduler {
 public:
  /// A view and how to render it in its host (e.g. the Qt widget's window, an offscreen window).
  void AddView(View* view, std::function<void()> render, std::function<bool()> shown = {});
  /// One display tick: renders the views that need it; returns how many were rendered.
  int RenderPendingViews();

 private:
  struct Entry {
    View* Target = nullptr;
    std::function<void()> Render;
    std::function<bool()> Shown;
    bool ChangedLastTick = false;
    bool Interactive = false;  // the last frame was drawn at the interactive level of detail
    bool RenderNow = false, InteractiveNow = false;  // this tick's decision
  };
  std::vector<Entry> Entries;
};

}  // namespace rp
