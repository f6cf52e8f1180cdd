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
  // Which views render this tick, and how: changed (drawn light when it changed on the previous
  // tick too), or stopped changing after being drawn light (one frame at full detail).
  std::vector<Entry*> due;
  for (Entry& entry : this->Entries) {
    const bool changed = entry.Target->NeedsRender();
    const bool shown = !entry.Shown || entry.Shown();
    entry.RenderNow = shown && (changed || entry.Interactive);
    entry.InteractiveNow = changed && entry.ChangedLastTick;
    entry.ChangedLastTick = changed && shown;
    if (entry.RenderNow) due.push_back(&entry);
  }
  // The slice pictures of all but the first view are made on worker threads while the views
  // before them render (each view's render waits on llvmpipe for part of its time); the first
  // makes its own as it renders.
  for (size_t i = 1; i < due.size(); ++i) due[i]->Target->StartPicture();
  for (Entry* entry : due) {
    entry->Target->SetInteractive(entry->InteractiveNow);
    entry->Render();
    entry->Interactive = entry->InteractiveNow;
  }
  // None outlives the tick (a view not rendered after all, say): volumes change between ticks.
  for (Entry* entry : due) entry->Target->WaitForPicture();
  return static_cast<int>(due.size());
}

}  // namespace rp
