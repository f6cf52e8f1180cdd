#include "rpRenderScheduler.h"

#include "rpView.h"

namespace rp {

void RenderScheduler::AddView(View* view, std::function<void()> render, std::function<bool()> shown) {
  Entry entry;
  entry.Target = view;
  entry.Render = std::move(render);
  entry.Shown = std::move(shown);
  this->Entries.push_back(std::move(entry));
}

int RenderScheduler::RenderPendingViews() {
  int rendered = 0;
  for (Entry& entry : this->Entries) {
    const bool changed = entry.Target->NeedsRender();
    const bool shown = !entry.Shown || entry.Shown();
    if (changed && shown) {
      // Changing on consecutive ticks: the view is in motion, draw it light.
      const bool interactive = entry.ChangedLastTick;
      entry.Target->SetInteractive(interactive);
      entry.Render();
      entry.Interactive = interactive;
      ++rendered;
    } else if (!changed && entry.Interactive && shown) {
      // It stopped: one frame at full detail.
      entry.Target->SetInteractive(false);
      entry.Render();
      entry.Interactive = false;
      ++rendered;
    }
    entry.ChangedLastTick = changed && shown;
  }
  return rendered;
}

}  // namespace rp
