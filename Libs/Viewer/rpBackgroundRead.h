#pragma once
// Reading files without freezing the viewer: the read runs on a worker thread while a progress
// dialog (with Cancel) shows the reader's progress and the Qt event loop keeps running (views
// render, timers fire). The read never touches the scene: it fills nodes that are not in a
// scene, and the caller adds them on the main thread once the read succeeded. Cancel (or a
// failure) leaves the scene as it was.
#include <functional>
#include <string>
#include <vector>

#include <QString>
#include <vtkSmartPointer.h>

#include "rpProgress.h"

class QWidget;
class vtkRPNode;

namespace rp {

/// What a background read produced.
struct BackgroundReadResult {
  bool Ok = false;
  bool Cancelled = false;
  std::string Error;
  std::vector<std::string> Warnings;
  std::vector<vtkSmartPointer<vtkRPNode>> Nodes;  // not in any scene yet
  /// The read found that its work belongs on the main thread (a scene file: its reader fills the
  /// scene as it goes) and did nothing else.
  bool LeftToMainThread = false;
};

/// The work: fills `result` (nodes, warnings, error) and returns success. Runs on a worker
/// thread: it must not touch the scene or any widget. `progress` may throw to cancel.
using BackgroundRead = std::function<bool(BackgroundReadResult& result, const ProgressCallback& progress)>;

/// Runs `read` on a worker thread and returns when it is done or cancelled, serving the event
/// loop meanwhile. A window-modal progress dialog titled `title` appears when the read takes
/// longer than a moment.
BackgroundReadResult RunBackgroundRead(QWidget* parent, const QString& title, BackgroundRead read);

}  // namespace rp
