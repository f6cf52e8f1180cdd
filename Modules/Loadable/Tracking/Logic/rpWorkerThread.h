#pragma once
// The thread shell every device I/O loop shares (the serial driver, the OpenIGTLink client and
// server, the replay, the Polaris simulator): start, stop (request + join), a sleep that ends
// at once when stop is requested, the last error text, and back-off between reconnections.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace rp {

class WorkerThread {
 public:
  WorkerThread() = default;
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;
  ~WorkerThread();  // stops and joins

  /// Runs `loop` on a new thread (nothing when one runs). The loop returns once
  /// StopRequested() is true (or when it is done by itself).
  void Start(std::function<void()> loop);
  /// Requests the stop, wakes a Sleep(), joins. Nothing when no thread runs.
  void Stop();
  bool Running() const { return this->Thread.joinable(); }
  bool StopRequested() const { return this->Stopping.load(std::memory_order_acquire); }
  /// Sleeps `seconds`; false (at once) when stop is requested.
  bool Sleep(double seconds);

  /// Error text, written by the loop on its error path and read by anyone.
  void Fail(const std::string& message);
  std::string LastError() const;
  void ClearError();

 private:
  std::thread Thread;
  std::atomic<bool> Stopping{false};
  std::mutex WakeMutex;  // Sleep/Stop only (never on a hot path)
  std::condition_variable Wake;
  mutable std::mutex TextMutex;
  std::string Error;
};

/// Waits between reconnection attempts: Initial, doubling up to Max; Reset after a success.
class Backoff {
 public:
  Backoff(double initialSeconds, double maxSeconds) : Initial(initialSeconds), Max(maxSeconds), Current(initialSeconds) {}
  /// The wait to use now; the next one doubles.
  double Next();
  void Reset() { this->Current = this->Initial; }

 private:
  double Initial, Max, Current;
};

/// "Data is ready" from an I/O thread to the main thread: an eventfd the main thread can wait on
/// (poll, QSocketNotifier). Notify() is one write(2): no lock, no allocation.
class ReadySignal {
 public:
  ReadySignal();
  ~ReadySignal();
  ReadySignal(const ReadySignal&) = delete;
  ReadySignal& operator=(const ReadySignal&) = delete;
  void Notify() const noexcept;
  /// Readable when notified since the last Drain(); -1 when the system has no eventfd left.
  int Fd() const { return this->Descriptor; }
  /// Main thread: clears the notification.
  void Drain() const noexcept;

 private:
  int Descriptor = -1;
};

}  // namespace rp
