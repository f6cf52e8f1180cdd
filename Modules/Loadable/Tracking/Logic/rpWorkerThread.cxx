#include "rpWorkerThread.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace rp {

WorkerThread::~WorkerThread() { this->Stop(); }

void WorkerThread::Start(std::function<void()> loop) {
  if (this->Thread.joinable()) return;
  this->Stopping.store(false, std::memory_order_release);
  this->Thread = std::thread(std::move(loop));
}

void WorkerThread::Stop() {
  if (!this->Thread.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(this->WakeMutex);
    this->Stopping.store(true, std::memory_order_release);
  }
  this->Wake.notify_all();
  this->Thread.join();
}

bool WorkerThread::Sleep(double seconds) {
  std::unique_lock<std::mutex> lock(this->WakeMutex);
  return !this->Wake.wait_for(lock, std::chrono::duration<double>(std::max(0.0, seconds)),
                              [this] { return this->Stopping.load(std::memory_order_acquire); });
}

void WorkerThread::Fail(const std::string& message) {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  this->Error = message;
}

std::string WorkerThread::LastError() const {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  return this->Error;
}

void WorkerThread::ClearError() {
  std::lock_guard<std::mutex> lock(this->TextMutex);
  this->Error.clear();
}

double Backoff::Next() {
  const double wait = this->Current;
  this->Current = std::min(2 * this->Current, this->Max);
  return wait;
}

ReadySignal::ReadySignal() : Descriptor(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {}

ReadySignal::~ReadySignal() {
  if (this->Descriptor >= 0) ::close(this->Descriptor);
}

void ReadySignal::Notify() const noexcept {
  if (this->Descriptor < 0) return;
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(this->Descriptor, &one, sizeof one);  // full counter: already signalled
}

void ReadySignal::Drain() const noexcept {
  if (this->Descriptor < 0) return;
  uint64_t count;
  [[maybe_unused]] const ssize_t n = ::read(this->Descriptor, &count, sizeof count);
}

}  // namespace rp
