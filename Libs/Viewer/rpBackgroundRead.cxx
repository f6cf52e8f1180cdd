#include "rpBackgroundRead.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include <QEventLoop>
#include <QProgressDialog>
#include <QTimer>

#include "vtkRPNode.h"

namespace rp {
namespace {

// Thrown from the progress callback when the user cancelled: unwinds the reader at its next
// progress report (the DICOM reader reports every file).
struct ReadCancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

// What the worker and the main thread share: the worker writes progress and the result, the
// main thread polls them and sets the cancel flag.
struct SharedState {
  std::atomic<bool> Cancel{false};
  std::atomic<bool> Done{false};
  std::mutex Mutex;
  double Fraction = 0.0;
  std::string Message;
  BackgroundReadResult Result;
};

}  // namespace

BackgroundReadResult RunBackgroundRead(QWidget* parent, const QString& title, BackgroundRead read) {
  auto state = std::make_shared<SharedState>();
  std::thread worker([state, read = std::move(read)]() {
    const ProgressCallback progress = [state](double fraction, const std::string& message) {
      if (state->Cancel) throw ReadCancelled();
      std::lock_guard<std::mutex> lock(state->Mutex);
      state->Fraction = fraction;
      state->Message = message;
    };
    BackgroundReadResult result;
    try {
      result.Ok = read(result, progress);
    } catch (const ReadCancelled&) {
      result.Ok = false;
    } catch (const std::bad_alloc&) {
      result.Ok = false;
      result.Error = "out of memory";
    } catch (const std::exception& e) {
      result.Ok = false;
      result.Error = e.what();
    }
    if (state->Cancel) {
      result.Ok = false;
      result.Cancelled = true;
      result.Error = "cancelled";
      result.Nodes.clear();  // released here, never added to a scene
    }
    {
      std::lock_guard<std::mutex> lock(state->Mutex);
      state->Result = std::move(result);
    }
    state->Done = true;
  });

  QProgressDialog dialog(title, "Cancel", 0, 1000, parent);
  dialog.setWindowTitle(title);
  dialog.setWindowModality(Qt::WindowModal);
  dialog.setMinimumDuration(400);  // quick reads finish before the dialog appears
  dialog.setAutoClose(false);
  dialog.setAutoReset(false);
  QEventLoop loop;
  QTimer poll;
  poll.setInterval(30);
  QObject::connect(&poll, &QTimer::timeout, [&]() {
    if (state->Done) {
      loop.quit();
      return;
    }
    // The Cancel button (or QProgressDialog::cancel()) marks the dialog: the worker stops at its
    // next progress report.
    if (dialog.wasCanceled() && !state->Cancel) {
      state->Cancel = true;
      dialog.setLabelText("Cancelling...");
    }
    double fraction;
    std::string message;
    {
      std::lock_guard<std::mutex> lock(state->Mutex);
      fraction = state->Fraction;
      message = state->Message;
    }
    if (!state->Cancel) {
      dialog.setValue(static_cast<int>(1000 * std::min(std::max(fraction, 0.0), 1.0)));
      if (!message.empty()) dialog.setLabelText(title + ": " + QString::fromStdString(message));
    }
  });
  poll.start();
  if (!state->Done) loop.exec();
  poll.stop();
  worker.join();
  dialog.reset();
  std::lock_guard<std::mutex> lock(state->Mutex);
  return std::move(state->Result);
}

}  // namespace rp
